//! PLY meshes (ASCII and binary, either endianness), read with `ply-rs-bw`. Vertex
//! positions `x y z`, optional normals `nx ny nz` and texture coordinates (`u v`, `s t`
//! or `texture_u texture_v`); other vertex properties are ignored. Faces come from
//! `vertex_indices` (or `vertex_index`) lists and polygons are fan-triangulated.

use glam::{Vec2, Vec3};
use penumbra_geometry::TriangleMesh;
use ply_rs_bw::parser::Parser;
use ply_rs_bw::ply::{DefaultElement, Encoding, Header, Property};
use std::path::Path;

fn scalar(p: &Property) -> Option<f64> {
    Some(match *p {
        Property::Char(v) => v as f64,
        Property::UChar(v) => v as f64,
        Property::Short(v) => v as f64,
        Property::UShort(v) => v as f64,
        Property::Int(v) => v as f64,
        Property::UInt(v) => v as f64,
        Property::Float(v) => v as f64,
        Property::Double(v) => v,
        _ => return None,
    })
}

fn list(p: &Property) -> Option<Vec<i64>> {
    Some(match p {
        Property::ListChar(v) => v.iter().map(|&x| x as i64).collect(),
        Property::ListUChar(v) => v.iter().map(|&x| x as i64).collect(),
        Property::ListShort(v) => v.iter().map(|&x| x as i64).collect(),
        Property::ListUShort(v) => v.iter().map(|&x| x as i64).collect(),
        Property::ListInt(v) => v.iter().map(|&x| x as i64).collect(),
        Property::ListUInt(v) => v.iter().map(|&x| x as i64).collect(),
        _ => return None,
    })
}

/// The first of `names` present in `e` as a number.
fn get(e: &DefaultElement, names: &[&str]) -> Option<f32> {
    names.iter().find_map(|n| e.get(*n)).and_then(scalar).map(|x| x as f32)
}

/// Loads the PLY file at `path`.
pub fn load(path: &Path) -> Result<TriangleMesh, String> {
    let file = std::fs::File::open(path).map_err(|e| e.to_string())?;
    let mut reader = std::io::BufReader::new(file);
    let ply = Parser::<DefaultElement>::new()
        .read_ply(&mut reader)
        .map_err(|e| format!("invalid PLY: {e}"))?;
    let place = |element: &str, i: usize, token: usize| place(path, &ply.header, element, i, token);
    let vertices = ply.payload.get("vertex").ok_or("the file has no `vertex` element")?;
    let faces = ply.payload.get("face").ok_or("the file has no `face` element")?;

    let mut mesh = TriangleMesh::default();
    let (mut normals, mut uvs) = (Vec::new(), Vec::new());
    for (i, v) in vertices.iter().enumerate() {
        let p = (get(v, &["x"]), get(v, &["y"]), get(v, &["z"]));
        let (Some(x), Some(y), Some(z)) = p else {
            return Err(format!(
                "{}: vertex {i} lacks a numeric x, y or z",
                place("vertex", i, 0)
            ));
        };
        mesh.positions.push(Vec3::new(x, y, z));
        if let (Some(nx), Some(ny), Some(nz)) = (get(v, &["nx"]), get(v, &["ny"]), get(v, &["nz"])) {
            normals.push(Vec3::new(nx, ny, nz));
        }
        if let (Some(u), Some(w)) = (get(v, &["u", "s", "texture_u"]), get(v, &["v", "t", "texture_v"])) {
            uvs.push(Vec2::new(u, w));
        }
    }
    let n = mesh.positions.len();
    mesh.normals = (normals.len() == n && n > 0).then_some(normals);
    mesh.uvs = (uvs.len() == n && n > 0).then_some(uvs);

    for (i, f) in faces.iter().enumerate() {
        let idx = ["vertex_indices", "vertex_index"]
            .iter()
            .find_map(|k| f.get(*k))
            .and_then(list)
            .ok_or_else(|| format!("{}: face {i} has no vertex_indices list", place("face", i, 0)))?;
        if idx.len() < 3 {
            return Err(format!(
                "{}: face {i} has {} vertices; at least 3 are needed",
                place("face", i, 0),
                idx.len()
            ));
        }
        if let Some(j) = idx.iter().position(|&x| !(0..n as i64).contains(&x)) {
            return Err(format!(
                "{}: face {i} uses vertex {}, but the file has {n} vertices",
                place("face", i, j + 1),
                idx[j]
            ));
        }
        let first = idx[0] as u32;
        for k in 1..idx.len() - 1 {
            mesh.indices.push([first, idx[k] as u32, idx[k + 1] as u32]);
        }
    }
    if mesh.indices.is_empty() {
        return Err("the file contains no faces".into());
    }
    mesh.validate().map_err(|e| e.to_string())?;
    Ok(mesh)
}

/// Where element `i` of `element` is in the file: in an ASCII file, its line and the column
/// of its `token`-th value (0: the line's first); in a binary one, the element and index.
fn place(path: &Path, header: &Header, element: &str, i: usize, token: usize) -> String {
    if header.encoding != Encoding::Ascii {
        return format!("{element} {i} (binary data)");
    }
    let before: usize = header
        .elements
        .values()
        .take_while(|e| e.name != element)
        .map(|e| e.count)
        .sum();
    let text = std::fs::read(path).unwrap_or_default();
    let text = String::from_utf8_lossy(&text);
    let mut lines = text.lines().enumerate();
    let Some((header_end, _)) = lines.find(|(_, l)| l.trim() == "end_header") else {
        return format!("{element} {i}");
    };
    let number = header_end + 1 + before + i;
    let line = lines.nth(before + i).map_or("", |(_, l)| l);
    let column = line
        .split_whitespace()
        .nth(token)
        .map_or(1, |t| t.as_ptr() as usize - line.as_ptr() as usize + 1);
    format!("line {}, column {column}", number + 1)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn write(name: &str, bytes: &[u8]) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!("penumbra-ply-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join(name);
        std::fs::write(&p, bytes).unwrap();
        p
    }

    const HEADER: &str = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\nproperty float confidence\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";

    #[test]
    fn ascii_quad_is_triangulated_and_extra_properties_skipped() {
        let p = write(
            "quad.ply",
            format!("{HEADER}0 0 0 1\n1 0 0 1\n1 1 0 1\n0 1 0 1\n4 0 1 2 3\n").as_bytes(),
        );
        let m = load(&p).unwrap();
        assert_eq!(m.positions.len(), 4);
        assert_eq!(m.indices, vec![[0, 1, 2], [0, 2, 3]]);
        assert!(m.normals.is_none());
    }

    #[test]
    fn binary_little_endian() {
        let mut bytes = b"ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar uint vertex_indices\nend_header\n".to_vec();
        for v in [[0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]] {
            v.iter().for_each(|x| bytes.extend_from_slice(&x.to_le_bytes()));
        }
        bytes.push(3);
        [0u32, 1, 2]
            .iter()
            .for_each(|i| bytes.extend_from_slice(&i.to_le_bytes()));
        let m = load(&write("bin.ply", &bytes)).unwrap();
        assert_eq!(m.indices, vec![[0, 1, 2]]);
        assert_eq!(m.positions[1], Vec3::X);
    }

    #[test]
    fn bad_files_are_errors() {
        assert!(load(&write("trunc.ply", &HEADER.as_bytes()[..40])).is_err());
        let p = write(
            "range.ply",
            format!("{HEADER}0 0 0 1\n1 0 0 1\n1 1 0 1\n0 1 0 1\n3 0 1 9\n").as_bytes(),
        );
        // The out-of-range index is the 4th value on line 15.
        let e = load(&p).unwrap_err();
        assert!(
            e.contains("line 15, column 7: face 0 uses vertex 9, but the file has 4 vertices"),
            "{e}"
        );
        assert!(load(Path::new("/nonexistent/x.ply")).is_err());
    }
}
