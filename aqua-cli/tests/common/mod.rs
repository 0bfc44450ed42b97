//! Helpers shared by the `aqua` command-line tests: run the binary, make a scratch folder.

#![allow(dead_code)]

use std::path::PathBuf;
use std::process::{Command, Output};

/// Runs the `aqua` binary built for these tests.
pub fn aqua(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_aqua"))
        .args(args)
        .output()
        .unwrap()
}

/// A fresh scratch folder `aqua-<group>-<pid>-<name>` in the temporary directory.
pub fn scratch(group: &str, name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("aqua-{group}-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}
