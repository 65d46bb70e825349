use super::*;
use crate::desc::{CameraKind, LightDesc};
use crate::formats::test_files::{error_at, folder};
use base64::Engine;
use penumbra_render::materials::{ConductorMaterial, PlasticMaterial};
use penumbra_render::{Material, Texture};

/// A quad from (-1, -1) to (1, 1) in the z = 0 plane facing +z, texture coordinates with
/// glTF's (0, 0) at its top left, two triangles: 48 bytes of positions, 32 of texture
/// coordinates, 12 of u16 indices.
pub fn quad_buffer() -> Vec<u8> {
    let mut b = Vec::new();
    for p in [
        [-1.0f32, -1.0, 0.0],
        [1.0, -1.0, 0.0],
        [1.0, 1.0, 0.0],
        [-1.0, 1.0, 0.0],
    ] {
        p.iter().for_each(|x| b.extend(x.to_le_bytes()));
    }
    for uv in [[0.0f32, 1.0], [1.0, 1.0], [1.0, 0.0], [0.0, 0.0]] {
        uv.iter().for_each(|x| b.extend(x.to_le_bytes()));
    }
    for i in [0u16, 1, 2, 0, 2, 3] {
        b.extend(i.to_le_bytes());
    }
    b
}

/// A document with the quad on node 0 (under `node` extra members), material `material`,
/// and `extra` top-level members (each ending in a comma); the buffer as `uri`.
pub fn quad_gltf(uri: &str, node: &str, material: &str, extra: &str) -> String {
    format!(
        r#"{{
  "asset": {{"version": "2.0"}},
  {extra}
  "scenes": [{{"nodes": [0]}}],
  "nodes": [{{"mesh": 0 {node}}}],
  "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0, "TEXCOORD_0": 1}}, "indices": 2, "material": 0}}]}}],
  "materials": [{material}],
  "buffers": [{{"byteLength": 92, "uri": "{uri}"}}],
  "bufferViews": [
    {{"buffer": 0, "byteOffset": 0, "byteLength": 48}},
    {{"buffer": 0, "byteOffset": 48, "byteLength": 32}},
    {{"buffer": 0, "byteOffset": 80, "byteLength": 12}}
  ],
  "accessors": [
    {{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-1, -1, 0], "max": [1, 1, 0]}},
    {{"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC2"}},
    {{"bufferView": 2, "componentType": 5123, "count": 6, "type": "SCALAR"}}
  ]
}}"#
    )
}

fn data_uri(bytes: &[u8]) -> String {
    format!(
        "data:application/octet-stream;base64,{}",
        base64::engine::general_purpose::STANDARD.encode(bytes)
    )
}

fn read_text(text: &str) -> SceneDesc {
    let dir = folder(&[("a.gltf", text)]);
    read(&dir.path().join("a.gltf")).unwrap_or_else(|e| panic!("{e}"))
}

/// A GLB container of `json` and `bin` (padded as the spec asks).
pub fn glb(json: &str, bin: &[u8]) -> Vec<u8> {
    let mut j = json.as_bytes().to_vec();
    while !j.len().is_multiple_of(4) {
        j.push(b' ');
    }
    let mut b = bin.to_vec();
    while !b.len().is_multiple_of(4) {
        b.push(0);
    }
    let total = 12 + 8 + j.len() + 8 + b.len();
    let mut out = b"glTF".to_vec();
    for w in [2u32, total as u32, j.len() as u32, 0x4E4F_534A] {
        out.extend(w.to_le_bytes());
    }
    out.extend(&j);
    out.extend((b.len() as u32).to_le_bytes());
    out.extend(0x004E_4942u32.to_le_bytes());
    out.extend(&b);
    out
}

/// Nodes, camera, light and material come through: the node's transform places the quad,
/// its camera looks down its -z, the KHR light shines down its node's -z; metallic 0 is the
/// plastic, metallic 1 the Schlick metal, in between a blend; alpha is roughness squared.
#[test]
fn nodes_cameras_lights_and_materials_map_onto_the_scene() {
    let uri = data_uri(&quad_buffer());
    let extra = r#""extensionsUsed": ["KHR_lights_punctual"],
  "extensions": {"KHR_lights_punctual": {"lights": [{"type": "spot", "color": [1, 0.5, 0.25], "intensity": 4, "spot": {"innerConeAngle": 0.2, "outerConeAngle": 0.5}}]}},
  "cameras": [{"type": "perspective", "perspective": {"yfov": 0.5, "aspectRatio": 1.5, "znear": 0.1}}],"#;
    let text = quad_gltf(
        &uri,
        r#", "translation": [0, 0, -2], "children": [1, 2]}, {"camera": 0, "translation": [0, 0, 5]}, {"extensions": {"KHR_lights_punctual": {"light": 0}}, "rotation": [0.7071068, 0, 0, 0.7071068]"#,
        r#"{"pbrMetallicRoughness": {"baseColorFactor": [0.2, 0.4, 0.6, 1], "metallicFactor": 0.5, "roughnessFactor": 0.3}}"#,
        extra,
    );
    let desc = read_text(&text);
    assert!(desc.warnings.is_empty(), "{:?}", desc.warnings);
    assert_eq!((desc.render.width, desc.render.height), (900, 600));
    // The camera: at (0, 0, 3), looking down -z, y up, not mirrored.
    let c = &desc.camera;
    assert!((c.position - Vec3::new(0.0, 0.0, 3.0)).length() < 1e-5, "{c:?}");
    assert!(
        ((c.target - c.position).normalize() - Vec3::NEG_Z).length() < 1e-5,
        "{c:?}"
    );
    assert!((c.up.normalize() - Vec3::Y).length() < 1e-5 && !c.mirrored, "{c:?}");
    assert!(matches!(c.kind, CameraKind::Perspective { fov, .. } if (fov - 0.5f32.to_degrees()).abs() < 1e-4));
    // The light: node 2 turned +90 degrees about x, so its -z points to +y (world).
    match &desc.lights[..] {
        [LightDesc::Spot {
            position,
            target,
            intensity,
            cone_angle,
            falloff_start,
        }] => {
            assert!((*position - Vec3::new(0.0, 0.0, -2.0)).length() < 1e-5);
            assert!(((*target - *position) - Vec3::Y).length() < 1e-5, "{target}");
            assert_eq!(*intensity, penumbra_core::Rgb::new(4.0, 2.0, 1.0));
            assert!(
                (cone_angle - 0.5f32.to_degrees()).abs() < 1e-4 && (falloff_start - 0.2f32.to_degrees()).abs() < 1e-4
            );
        }
        other => panic!("{other:?}"),
    }
    assert!(desc.environment.is_none(), "a scene with lights gets no default sky");
    // The quad, moved to z = -2, with its material.
    assert_eq!(desc.shapes.len(), 1);
    assert_eq!(desc.shapes[0].transform.point(Vec3::ZERO), Vec3::new(0.0, 0.0, -2.0));
    let m = &desc.materials[desc.shapes[0].material.unwrap()].material;
    let Material::TwoSided(inner) = m else { panic!("{m:?}") };
    let Material::Blend { a, b, weight } = &**inner else {
        panic!("{inner:?}")
    };
    assert_eq!(*weight, Texture::Constant(penumbra_core::Rgb::splat(0.5)));
    assert!(
        matches!(&**a, Material::Plastic(PlasticMaterial { eta, roughness: Some(r), diffuse: Texture::Constant(d), .. })
            if *eta == 1.5 && r.alpha_u == Texture::Constant(penumbra_core::Rgb::splat(0.09f32)) && *d == penumbra_core::Rgb::new(0.2, 0.4, 0.6)),
        "{a:?}"
    );
    assert!(
        matches!(&**b, Material::Conductor(ConductorMaterial { fresnel: penumbra_render::bsdfs::MetalFresnel::Schlick, specular: Texture::Constant(s), .. })
            if *s == penumbra_core::Rgb::new(0.2, 0.4, 0.6)),
        "{b:?}"
    );
    // The same document in a GLB with its buffer in the binary chunk reads the same.
    let bin_text = text.replace(&format!(r#", "uri": "{uri}""#), "");
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("a.glb"), glb(&bin_text, &quad_buffer())).unwrap();
    let from_glb = read(&dir.path().join("a.glb")).unwrap_or_else(|e| panic!("{e}"));
    let positions = |d: &SceneDesc| match &d.shapes[0].kind {
        ShapeKind::Mesh(m) => (m.positions.clone(), m.uvs.clone(), m.indices.clone()),
        k => panic!("{k:?}"),
    };
    assert_eq!(positions(&from_glb), positions(&desc));
    // Without camera or lights: a framing camera, the default sky and key light.
    let bare = quad_gltf(&uri, "", "{}", "");
    let desc = read_text(&bare);
    assert!(desc.environment.is_some() && desc.lights.len() == 1);
    assert!(c.position != desc.camera.position);
}

/// A node used twice becomes two instances of one shared mesh.
#[test]
fn meshes_used_by_several_nodes_are_instanced() {
    let uri = data_uri(&quad_buffer());
    let text = quad_gltf(&uri, r#"}, {"mesh": 0, "translation": [3, 0, 0]"#, "{}", "")
        .replace(r#""scenes": [{"nodes": [0]}]"#, r#""scenes": [{"nodes": [0, 1]}]"#);
    let desc = read_text(&text);
    assert_eq!(desc.meshes.len(), 1);
    assert!(desc
        .shapes
        .iter()
        .all(|s| matches!(s.kind, ShapeKind::Instance { mesh: 0 })));
    assert_eq!(desc.shapes[1].transform.point(Vec3::ZERO), Vec3::new(3.0, 0.0, 0.0));
}

/// Malformed documents: each error names the file, line and column of the member at fault.
#[test]
fn errors_point_at_the_member_at_fault() {
    let uri = data_uri(&quad_buffer());
    let good = quad_gltf(&uri, "", "{}", "");
    let cases: Vec<(String, &str)> = vec![
        (good.replace(r#""asset""#, r#"asset"#), "a.gltf:2:3 | malformed glTF JSON"),
        // Every other case points at the value at fault (checked by hand once: the `7`, the
        // count, the byteLength, the type, the componentType, the stride, the URI, the
        // required extension, the yfov, the indices).
        (good.replace(r#""indices": 2"#, r#""indices": 7"#), "a.gltf:6:90 | invalid glTF: an index out of range at `meshes[0].primitives[0].indices`"),
        (good.replace(r#""count": 6"#, r#""count": 7"#), "a.gltf:17:55 | 7 elements of 2 bytes every 2 from byte 0 run past the view's 12 bytes"),
        (good.replace(r#""byteLength": 92"#, r#""byteLength": 1000000000000"#), "a.gltf:8:30 | the buffer holds 92 bytes, fewer than its byteLength"),
        (good.replace(r#""type": "VEC2""#, r#""type": "VEC3""#), "a.gltf:16:66 | expected a Vec2 accessor, found Vec3"),
        (good.replace(r#""componentType": 5123"#, r#""componentType": 5126"#), "a.gltf:17:40 | vertex indices must be unsigned integer scalars"),
        (good.replace(r#""nodes": [{"mesh": 0 }]"#, r#""nodes": [{"mesh": 0, "children": [0]}]"#), "a.gltf:5:13 | node 0 is reached twice"),
        (good.replace(r#""byteOffset": 48, "byteLength": 32}"#, r#""byteOffset": 48, "byteLength": 32, "byteStride": 4}"#), "a.gltf:11:69 | a stride of 4 bytes is less than the 8-byte elements"),
        (good.replace(&uri, "missing.bin"), "a.gltf:8:41 | cannot read"),
        (good.replace(r#""extensionsUsed""#, "").replacen(r#""scenes""#, r#""extensionsUsed": ["KHR_draco_mesh_compression"], "extensionsRequired": ["KHR_draco_mesh_compression"], "scenes""#, 1), "a.gltf:4:76 | the file requires KHR_draco_mesh_compression"),
        (good.replacen(r#""scenes""#, r#""cameras": [{"type": "perspective", "perspective": {"yfov": 4, "znear": 1}}], "scenes""#, 1).replace(r#""mesh": 0 }"#, r#""mesh": 0, "camera": 0}"#), "a.gltf:4:63 | the vertical field of view must be between 0 and pi radians"),
    ];
    // The out-of-range vertex index: index 9 of a 4-vertex quad (u16 9 at byte 80).
    let mut buffer = quad_buffer();
    buffer[80] = 9;
    let bad_index = quad_gltf(&data_uri(&buffer), "", "{}", "");
    let mut cases = cases;
    cases.push((
        bad_index,
        "a.gltf:6:90 | vertex index 9 is out of range: the primitive has 4 vertices",
    ));
    let mut wrong = Vec::new();
    for (text, expected) in &cases {
        let got = error_at(&[("a.gltf", text)], read);
        let (at, message) = expected.split_once(" | ").unwrap();
        if !(got.starts_with(&format!("{at} |")) && got.contains(message)) {
            let (line, col) = at[7..].split_once(':').unwrap();
            let row = text.lines().nth(line.parse::<usize>().unwrap() - 1).unwrap_or("");
            let from = row.get(col.parse::<usize>().unwrap() - 1..).unwrap_or("");
            wrong.push(format!("expected {expected}\n     got {got}\n     there: {from}"));
        }
    }
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}

/// Extensions we can do without are warnings, once each; primitives of lines are skipped.
#[test]
fn unsupported_things_warn_once() {
    let uri = data_uri(&quad_buffer());
    let text = quad_gltf(
        &uri,
        "",
        r#"{"alphaMode": "MASK"}, {"alphaMode": "BLEND"}"#,
        r#""extensionsUsed": ["KHR_materials_clearcoat", "KHR_texture_basisu"], "extensionsRequired": ["KHR_materials_clearcoat"],"#,
    );
    let desc = read_text(&text);
    let joined = desc.warnings.join("\n");
    assert!(
        joined.contains("a.gltf:3:") && joined.contains("KHR_materials_clearcoat is not supported"),
        "{joined}"
    );
    assert!(joined.contains("KHR_texture_basisu is not supported"), "{joined}");
    assert!(joined.contains("alphaMode Mask is not supported"), "{joined}");
    assert_eq!(desc.warnings.iter().filter(|w| w.contains("alphaMode")).count(), 1);
    let lines = quad_gltf(&uri, "", "{}", "").replace(r#""material": 0}"#, r#""material": 0, "mode": 1}"#);
    let dir = folder(&[("a.gltf", &lines)]);
    let e = read(&dir.path().join("a.gltf")).expect_err("nothing to draw");
    assert!(e.to_string().contains("no triangles"), "{e}");
}

/// The picture is the right way round: a quad whose emissive texture is red, green, blue
/// and white in its top-left, top-right, bottom-left and bottom-right quarters, seen by
/// the file's camera from the front, shows each colour in that quarter of the image (so
/// texture coordinates, the camera's handedness and textured emission all hold).
#[test]
fn the_picture_is_the_right_way_round() {
    let mut png = Vec::new();
    let pixels = [[255u8, 0, 0], [0, 255, 0], [0, 0, 255], [255, 255, 255]];
    image::RgbImage::from_fn(2, 2, |x, y| image::Rgb(pixels[(y * 2 + x) as usize]))
        .write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
        .unwrap();
    let png_uri = format!(
        "data:image/png;base64,{}",
        base64::engine::general_purpose::STANDARD.encode(&png)
    );
    let extra = format!(
        r#""cameras": [{{"type": "perspective", "perspective": {{"yfov": 0.6, "aspectRatio": 1, "znear": 0.1}}}}],
  "images": [{{"uri": "{png_uri}"}}], "textures": [{{"source": 0}}],"#
    );
    let text = quad_gltf(
        &data_uri(&quad_buffer()),
        r#", "children": [1]}, {"camera": 0, "translation": [0, 0, 3]"#,
        r#"{"pbrMetallicRoughness": {"baseColorFactor": [0, 0, 0, 1]}, "emissiveFactor": [1, 1, 1], "emissiveTexture": {"index": 0}}"#,
        &extra,
    );
    let desc = read_text(&text);
    assert!(desc.shapes[0].emission.as_ref().is_some_and(|e| e.texture.is_some()));
    let scene = crate::build_scene(&desc).unwrap();
    let (w, h) = (desc.render.width as f32, desc.render.height as f32);
    for (k, (fx, fy)) in [(0.25, 0.25), (0.75, 0.25), (0.25, 0.75), (0.75, 0.75)]
        .into_iter()
        .enumerate()
    {
        let ray = scene
            .camera
            .generate_ray(glam::Vec2::new(fx * w, fy * h), glam::Vec2::splat(0.5));
        let it = scene.intersect(&ray, f32::INFINITY).expect("the quad fills the view");
        let c = scene.emitted(&it);
        let want = pixels[k].map(|x| x as f32 / 255.0);
        let got = [c.r, c.g, c.b];
        assert!(
            got.iter().zip(want).all(|(g, w)| (g - w).abs() < 0.1),
            "quarter {k}: {got:?}, expected {want:?}"
        );
    }
}
