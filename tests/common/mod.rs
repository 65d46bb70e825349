//! Helpers the command-line tests share.

use std::path::Path;
use std::process::{Command, Output};

/// Runs the `penumbra` binary in `dir` with `args`.
pub fn penumbra(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_penumbra"))
        .current_dir(dir)
        .args(args)
        .output()
        .expect("runs")
}

/// Output bytes as text.
pub fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}
