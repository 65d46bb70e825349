//! What every fuzz target does: write the input as a scene file of one format (in a folder
//! of this process's own, so that relative includes and meshes resolve there), read it, and
//! build what reads. Any panic, hang or unbounded allocation is a finding; errors are fine.

use std::path::PathBuf;

/// Reads `data` as a scene file with extension `ext`, and builds it if it reads.
pub fn read_as(ext: &str, data: &[u8]) {
    let dir = std::env::temp_dir().join(format!("penumbra-fuzz-{}", std::process::id()));
    let _ = std::fs::create_dir_all(&dir);
    let path: PathBuf = dir.join(format!("scene.{ext}"));
    if std::fs::write(&path, data).is_err() {
        return;
    }
    if let Ok(desc) = penumbra_scene::read_scene(&path) {
        let _ = penumbra_scene::build_scene(&desc);
    }
}
