//! Scene readers, one per format, chosen by file extension. Each produces a [`SceneDesc`].
//!
//! Adding a format: a new module with a `read(&Arc<SourceFile>) -> Result<SceneDesc>` and
//! one arm in [`read_scene`].

pub mod native;
pub mod obj;
pub mod ply;

use crate::{SceneDesc, SceneError, SourceFile};
use std::path::Path;

/// Reads the scene file at `path`, choosing the reader by its extension.
pub fn read_scene(path: &Path) -> Result<SceneDesc, SceneError> {
    let ext = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    match ext.as_deref() {
        Some("toml") => {
            let text = std::fs::read_to_string(path).map_err(|e| SceneError::io(path, e))?;
            native::read(&SourceFile::new(path, text))
        }
        _ => Err(SceneError::io(
            path,
            "unsupported scene format: expected a .toml scene file (the native format)",
        )),
    }
}
