//! Mitsuba's binary grid files (`.vol`, read by Mitsuba 0.6 and 3's `gridvolume`): the
//! bytes `VOL` and the version 3; then as little-endian 32-bit numbers the encoding (1:
//! 32-bit floats, the only one Mitsuba 3 reads), the resolution x, y, z, the channel count
//! and a bounding box (min x, y, z, max x, y, z); then the values, channels fastest, then
//! x, y and z.
//!
//! The header is checked against the file's length before anything is allocated, so a
//! corrupt or truncated file is an error naming what disagrees, never an allocation of
//! whatever size the header claims.

use glam::{UVec3, Vec3};
use std::io::Read;
use std::path::Path;

/// The header's length in bytes.
const HEADER: u64 = 48;
/// The most cells along an axis (pbrt-v4's `uniformgrid` limit is the same).
pub const MAX_RES: u32 = 4096;
/// The most values a grid may hold: 2^30 (4 GiB of floats).
pub const MAX_VALUES: u64 = 1 << 30;

/// A grid as read from a `.vol` file.
#[derive(Clone, Debug, PartialEq)]
pub struct VolGrid {
    pub res: UVec3,
    pub channels: u32,
    /// The box the file says the grid covers (Mitsuba 3 uses it only with `use_grid_bbox`).
    pub bbox: [Vec3; 2],
    /// `res.x * res.y * res.z * channels` values, channels fastest.
    pub values: Vec<f32>,
}

/// Reads the grid in `path`; the error says what is wrong with the file.
pub fn read(path: &Path) -> Result<VolGrid, String> {
    let mut file = std::fs::File::open(path).map_err(|e| format!("cannot open {}: {e}", path.display()))?;
    let length = file.metadata().map_err(|e| e.to_string())?.len();
    let mut header = [0u8; HEADER as usize];
    file.read_exact(&mut header)
        .map_err(|_| format!("{} is too short for a .vol header ({length} bytes)", path.display()))?;
    let (res, channels, bbox) = parse_header(&header).map_err(|e| format!("{}: {e}", path.display()))?;
    let count = res.x as u64 * res.y as u64 * res.z as u64 * channels as u64;
    let expected = HEADER + 4 * count;
    if length != expected {
        return Err(format!(
            "{}: a {}x{}x{} grid of {channels} channel(s) takes {expected} bytes, the file has {length}",
            path.display(),
            res.x,
            res.y,
            res.z
        ));
    }
    let mut bytes = vec![0u8; 4 * count as usize];
    file.read_exact(&mut bytes)
        .map_err(|e| format!("{}: {e}", path.display()))?;
    let values = bytes
        .chunks_exact(4)
        .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
        .collect();
    Ok(VolGrid {
        res,
        channels,
        bbox,
        values,
    })
}

fn parse_header(h: &[u8; HEADER as usize]) -> Result<(UVec3, u32, [Vec3; 2]), String> {
    if &h[..3] != b"VOL" {
        return Err("not a .vol file (it does not begin with `VOL`)".into());
    }
    if h[3] != 3 {
        return Err(format!("version {} of the .vol format is not read (3 is)", h[3]));
    }
    let word = |i: usize| [h[4 + 4 * i], h[5 + 4 * i], h[6 + 4 * i], h[7 + 4 * i]];
    let int = |i: usize| i32::from_le_bytes(word(i));
    let float = |i: usize| f32::from_le_bytes(word(i));
    if int(0) != 1 {
        return Err(format!(
            "encoding {} is not read (1, 32-bit floats, is: Mitsuba 3 reads no other)",
            int(0)
        ));
    }
    let mut res = [0u32; 3];
    for (axis, r) in res.iter_mut().enumerate() {
        let v = int(1 + axis);
        if !(1..=MAX_RES as i32).contains(&v) {
            return Err(format!(
                "resolution {} along {} is out of range (1 to {MAX_RES})",
                v,
                ["x", "y", "z"][axis]
            ));
        }
        *r = v as u32;
    }
    let channels = int(4);
    if !(1..=4).contains(&channels) {
        return Err(format!("{channels} channels is out of range (1 to 4)"));
    }
    let res = UVec3::from(res);
    let count = res.x as u64 * res.y as u64 * res.z as u64 * channels as u64;
    if count > MAX_VALUES {
        return Err(format!(
            "{}x{}x{} cells of {channels} channel(s) is more than the {MAX_VALUES} values a grid may hold",
            res.x, res.y, res.z
        ));
    }
    let bbox = [
        Vec3::new(float(5), float(6), float(7)),
        Vec3::new(float(8), float(9), float(10)),
    ];
    Ok((res, channels as u32, bbox))
}

/// Writes a grid as a `.vol` file (for tests and the scene generators).
pub fn write(path: &Path, grid: &VolGrid) -> std::io::Result<()> {
    let mut bytes = Vec::with_capacity(HEADER as usize + 4 * grid.values.len());
    bytes.extend_from_slice(b"VOL\x03");
    for v in [1, grid.res.x, grid.res.y, grid.res.z, grid.channels] {
        bytes.extend_from_slice(&(v as i32).to_le_bytes());
    }
    for v in grid.bbox[0].to_array().into_iter().chain(grid.bbox[1].to_array()) {
        bytes.extend_from_slice(&v.to_le_bytes());
    }
    for v in &grid.values {
        bytes.extend_from_slice(&v.to_le_bytes());
    }
    std::fs::write(path, bytes)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid() -> VolGrid {
        VolGrid {
            res: UVec3::new(3, 2, 2),
            channels: 1,
            bbox: [Vec3::ZERO, Vec3::new(1.0, 2.0, 3.0)],
            values: (0..12).map(|i| i as f32 * 0.5).collect(),
        }
    }

    fn temp(name: &str) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!("penumbra-vol-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        dir.join(name)
    }

    #[test]
    fn a_written_grid_reads_back() {
        let path = temp("round.vol");
        write(&path, &grid()).unwrap();
        assert_eq!(read(&path).unwrap(), grid());
    }

    #[test]
    fn bad_files_are_errors_that_say_what_is_wrong() {
        let path = temp("bad.vol");
        write(&path, &grid()).unwrap();
        let good = std::fs::read(&path).unwrap();
        type Spoil = Box<dyn Fn(&mut Vec<u8>)>;
        let cases: [(&str, Spoil); 6] = [
            ("does not begin with `VOL`", Box::new(|b| b[0] = b'X')),
            ("version 2", Box::new(|b| b[3] = 2)),
            ("encoding 3", Box::new(|b| b[4] = 3)),
            ("takes 96 bytes, the file has 92", Box::new(|b| b.truncate(92))),
            ("resolution 0 along y", Box::new(|b| b[12] = 0)),
            (
                "more than the",
                Box::new(|b| {
                    for at in [8, 12, 16] {
                        b[at..at + 4].copy_from_slice(&4096i32.to_le_bytes());
                    }
                }),
            ),
        ];
        for (expected, spoil) in cases {
            let mut bytes = good.clone();
            spoil(&mut bytes);
            std::fs::write(&path, &bytes).unwrap();
            let e = read(&path).unwrap_err();
            assert!(e.contains(expected), "{expected}: {e}");
        }
        std::fs::write(&path, &good[..20]).unwrap();
        assert!(read(&path).unwrap_err().contains("too short"));
    }
}
