//! Helpers for the readers' tests: scene files written into a fresh folder, and where an
//! error points.

use crate::SceneError;
use std::path::Path;

/// Writes `files` (name, text) into a fresh folder; returns it.
pub fn folder(files: &[(&str, &str)]) -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    for (name, text) in files {
        let p = dir.path().join(name);
        std::fs::create_dir_all(p.parent().unwrap()).unwrap();
        std::fs::write(p, text).unwrap();
    }
    dir
}

/// The error of reading the first of `files` with `read`, as `file:line:column | message`.
pub fn error_at<T: std::fmt::Debug>(files: &[(&str, &str)], read: impl Fn(&Path) -> Result<T, SceneError>) -> String {
    error_at_in(&folder(files), files[0].0, read)
}

/// The error of reading `name` in `dir` with `read`, as `file:line:column | message`.
pub fn error_at_in<T: std::fmt::Debug>(
    dir: &tempfile::TempDir,
    name: &str,
    read: impl Fn(&Path) -> Result<T, SceneError>,
) -> String {
    let err = read(&dir.path().join(name)).expect_err("an error");
    let location = err.location().map(|l| {
        let (line, col) = l.file.line_col(l.span.start);
        format!(
            "{}:{line}:{col}",
            Path::new(&l.file.path).file_name().unwrap().to_string_lossy()
        )
    });
    format!("{} | {err}", location.unwrap_or_default())
}
