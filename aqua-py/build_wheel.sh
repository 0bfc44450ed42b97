#!/usr/bin/env bash
# Builds one wheel holding both the Python module `aqua` and the `aqua` command.
#
#   bash aqua-py/build_wheel.sh            # release build; the wheel lands in target/wheels/
#   bash aqua-py/build_wheel.sh --debug    # packages the debug `aqua` that `cargo test
#                                          # --workspace` built (what CI checks)
#   pip install target/wheels/aqua-*.whl
#
# Needs cargo and maturin (`pip install "maturin>=1.9.4,<2"`). The command is the binary of
# aqua-cli, copied into the wheel's data directory (aqua.data/scripts/, see pyproject.toml):
# pip installs it next to `python` in the environment's bin/ folder.
set -euo pipefail
cd "$(dirname "$0")"
profile=release
[ "${1:-}" = "--debug" ] && profile=debug
target="${CARGO_TARGET_DIR:-$PWD/../target}"
if [ "$profile" = release ]; then
  cargo build --release -p aqua-cli
elif [ ! -x "$target/debug/aqua" ]; then
  # `cargo build -p aqua-cli` resolves dependency features for aqua-cli alone, so after `cargo
  # test --workspace` it compiles every dependency a second time: reuse that build's binary.
  cargo build -p aqua-cli
fi
rm -rf aqua.data
mkdir -p aqua.data/scripts
cp "$target/$profile/aqua" aqua.data/scripts/aqua
if [ "$profile" = release ]; then
  # The release profile keeps debug info (for profiling); the wheel does not need it.
  if command -v strip >/dev/null 2>&1; then strip aqua.data/scripts/aqua; fi
  maturin build --release --strip --out "$target/wheels"
else
  maturin build --out "$target/wheels"
fi
