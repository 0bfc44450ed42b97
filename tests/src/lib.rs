//! Cross-crate end-to-end checks live in tests/tests/.
