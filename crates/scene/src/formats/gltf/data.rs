//! The binary data of a glTF document: its buffers (the GLB's own chunk, files beside it or
//! base64 `data:` URIs), the accessors that view them, and its images, each read with every
//! offset, count and stride checked against what is really there, so that a malformed file
//! is an error naming the JSON member at fault, never a panic or an allocation its data
//! cannot back.

use super::Fail;
use base64::Engine;
use gltf::accessor::{DataType, Dimensions};
use gltf::Document;
use penumbra_core::Rgb;
use std::path::Path;
use std::sync::Arc;

/// The largest accessor without a buffer view (all zeros) we build, in elements.
const MAX_ZERO_ELEMENTS: usize = 1 << 24;

/// The bytes of a `data:` URI (base64) or of a file named relative to `dir`.
fn read_uri(uri: &str, dir: &Path, limit: Option<usize>) -> Result<Vec<u8>, String> {
    if let Some(rest) = uri.strip_prefix("data:") {
        let (_, payload) = rest.split_once(";base64,").ok_or("a data: URI that is not base64")?;
        return base64::engine::general_purpose::STANDARD
            .decode(payload.trim())
            .map_err(|e| format!("its base64 data is malformed: {e}"));
    }
    if uri.contains("://") && !uri.starts_with("file://") {
        return Err(format!(
            "`{uri}`: only files beside the scene and data: URIs can be read"
        ));
    }
    let name = uri.strip_prefix("file://").unwrap_or(uri);
    let name = urlencoding::decode(name).map_err(|_| format!("`{uri}` is not a valid URI (bad percent-encoding)"))?;
    let path = dir.join(&*name);
    let meta = std::fs::metadata(&path).map_err(|e| format!("cannot read {}: {e}", path.display()))?;
    if let Some(limit) = limit.filter(|&l| (meta.len() as u128) < l as u128) {
        return Err(format!(
            "{} has {} bytes, fewer than the {limit} the buffer claims",
            path.display(),
            meta.len()
        ));
    }
    std::fs::read(&path).map_err(|e| format!("cannot read {}: {e}", path.display()))
}

/// The document's buffers, in order.
pub struct Buffers(Vec<Vec<u8>>);

impl Buffers {
    pub fn empty() -> Self {
        Buffers(Vec::new())
    }

    /// Reads every buffer: the GLB's binary chunk `blob` for the one without a URI, the
    /// others from `dir` or their data URIs; each must hold at least its `byteLength`.
    pub fn load(doc: &Document, blob: Option<Vec<u8>>, dir: &Path) -> Result<Self, Fail> {
        let mut blob = blob;
        let mut out = Vec::new();
        for b in doc.buffers() {
            let path = format!("buffers[{}]", b.index());
            let data = match b.source() {
                gltf::buffer::Source::Bin => blob
                    .take()
                    .ok_or_else(|| Fail::new(&path, "the buffer is the GLB's binary chunk, which this file lacks"))?,
                gltf::buffer::Source::Uri(uri) => {
                    read_uri(uri, dir, Some(b.length())).map_err(|m| Fail::new(format!("{path}.uri"), m))?
                }
            };
            if data.len() < b.length() {
                return Err(Fail::new(
                    format!("{path}.byteLength"),
                    format!(
                        "the buffer holds {} bytes, fewer than its byteLength {}",
                        data.len(),
                        b.length()
                    ),
                ));
            }
            out.push(data);
        }
        Ok(Buffers(out))
    }

    /// The bytes of buffer view `view`, checked against its buffer.
    fn view(&self, view: &gltf::buffer::View) -> Result<&[u8], Fail> {
        let buffer = &self.0[view.buffer().index()];
        let (start, len) = (view.offset(), view.length());
        start
            .checked_add(len)
            .and_then(|end| buffer.get(start..end))
            .ok_or_else(|| {
                Fail::new(
                    format!("bufferViews[{}].byteLength", view.index()),
                    format!(
                        "the view's bytes {start}..{} run past its buffer's {} bytes",
                        start as u128 + len as u128,
                        buffer.len()
                    ),
                )
            })
    }

    /// The elements of `accessor` as floats, `dims` numbers each, integers converted as the
    /// accessor says (normalized to [0, 1] or [-1, 1], or as they are), checked: its type,
    /// and every byte it reads inside its view.
    pub fn floats(&self, accessor: &gltf::Accessor, dims: Dimensions) -> Result<Vec<f32>, Fail> {
        let path = format!("accessors[{}]", accessor.index());
        if accessor.dimensions() != dims {
            return Err(Fail::new(
                format!("{path}.type"),
                format!("expected a {dims:?} accessor, found {:?}", accessor.dimensions()),
            ));
        }
        let n = dims.multiplicity();
        let kind = accessor.data_type();
        let normalized = accessor.normalized();
        let convert = move |b: &[u8]| -> f32 {
            match kind {
                DataType::F32 => f32::from_le_bytes([b[0], b[1], b[2], b[3]]),
                DataType::U8 if normalized => b[0] as f32 / 255.0,
                DataType::U8 => b[0] as f32,
                DataType::I8 if normalized => (b[0] as i8 as f32 / 127.0).max(-1.0),
                DataType::I8 => b[0] as i8 as f32,
                DataType::U16 if normalized => u16::from_le_bytes([b[0], b[1]]) as f32 / 65535.0,
                DataType::U16 => u16::from_le_bytes([b[0], b[1]]) as f32,
                DataType::I16 if normalized => (i16::from_le_bytes([b[0], b[1]]) as f32 / 32767.0).max(-1.0),
                DataType::I16 => i16::from_le_bytes([b[0], b[1]]) as f32,
                DataType::U32 => u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f32,
            }
        };
        self.elements(accessor, n, &path)?
            .map(|els| {
                Ok(els
                    .flat_map(|e| (0..n).map(move |k| convert(&e[k * kind.size()..])))
                    .collect())
            })
            .unwrap_or_else(|| {
                (accessor.count() <= MAX_ZERO_ELEMENTS)
                    .then(|| vec![0.0; accessor.count() * n])
                    .ok_or_else(|| {
                        Fail::new(
                            format!("{path}.count"),
                            "too many elements for an accessor without data",
                        )
                    })
            })
    }

    /// The elements of a scalar integer accessor (vertex indices).
    pub fn indices(&self, accessor: &gltf::Accessor) -> Result<Vec<u32>, Fail> {
        let path = format!("accessors[{}]", accessor.index());
        let kind = accessor.data_type();
        if accessor.dimensions() != Dimensions::Scalar || !matches!(kind, DataType::U8 | DataType::U16 | DataType::U32)
        {
            return Err(Fail::new(
                format!("{path}.componentType"),
                "vertex indices must be unsigned integer scalars",
            ));
        }
        let els = self
            .elements(accessor, 1, &path)?
            .ok_or_else(|| Fail::new(&path, "vertex indices need a bufferView"))?;
        Ok(els
            .map(|b| match kind {
                DataType::U8 => b[0] as u32,
                DataType::U16 => u16::from_le_bytes([b[0], b[1]]) as u32,
                _ => u32::from_le_bytes([b[0], b[1], b[2], b[3]]),
            })
            .collect())
    }

    /// The byte slices of `accessor`'s elements (`n` components each); `None` when it has
    /// no view (its elements are zeros).
    fn elements<'a>(
        &'a self,
        accessor: &gltf::Accessor,
        n: usize,
        path: &str,
    ) -> Result<Option<impl Iterator<Item = &'a [u8]> + 'a>, Fail> {
        if accessor.sparse().is_some() {
            return Err(Fail::new(
                format!("{path}.sparse"),
                "sparse accessors are not supported",
            ));
        }
        let Some(view) = accessor.view() else {
            return Ok(None);
        };
        let bytes = self.view(&view)?;
        let size = accessor.data_type().size() * n;
        let stride = view.stride().unwrap_or(size);
        if stride < size {
            return Err(Fail::new(
                format!("bufferViews[{}].byteStride", view.index()),
                format!("a stride of {stride} bytes is less than the {size}-byte elements it strides"),
            ));
        }
        let (offset, count) = (accessor.offset(), accessor.count());
        let end = match count {
            0 => Some(offset),
            _ => (count - 1)
                .checked_mul(stride)
                .and_then(|s| s.checked_add(offset))
                .and_then(|s| s.checked_add(size)),
        };
        if end.is_none_or(|end| end > bytes.len()) {
            return Err(Fail::new(
                format!("{path}.count"),
                format!(
                    "{count} elements of {size} bytes every {stride} from byte {offset} run past the view's {} bytes",
                    bytes.len()
                ),
            ));
        }
        Ok(Some(
            (0..count).map(move |i| &bytes[offset + i * stride..offset + i * stride + size]),
        ))
    }

    /// Decodes image `image` (PNG or JPEG, from a file, a data URI or a buffer view) to
    /// RGB in [0, 1] as stored (not yet linearized).
    pub fn image(&self, image: &gltf::Image, dir: &Path) -> Result<Arc<RawImage>, Fail> {
        let path = format!("images[{}]", image.index());
        let bytes: std::borrow::Cow<[u8]> = match image.source() {
            gltf::image::Source::Uri { uri, .. } => read_uri(uri, dir, None)
                .map_err(|m| Fail::new(format!("{path}.uri"), m))?
                .into(),
            gltf::image::Source::View { view, .. } => self.view(&view)?.into(),
        };
        let mut reader = image::ImageReader::new(std::io::Cursor::new(&*bytes))
            .with_guessed_format()
            .map_err(|e| Fail::new(&path, e.to_string()))?;
        let mut limits = image::Limits::default();
        limits.max_alloc = Some(crate::image_input::MAX_INPUT_PIXELS * 16);
        reader.limits(limits);
        let decoded = reader
            .decode()
            .map_err(|e| Fail::new(&path, format!("cannot decode the image: {e}")))?;
        let rgb = decoded.to_rgb32f();
        if rgb.width() == 0 || rgb.height() == 0 {
            return Err(Fail::new(&path, "the image is empty"));
        }
        Ok(Arc::new(RawImage {
            width: rgb.width() as usize,
            height: rgb.height() as usize,
            pixels: rgb.pixels().map(|p| Rgb::new(p[0], p[1], p[2])).collect(),
        }))
    }
}

/// An image's pixels as stored in the file, in [0, 1], rows from the top.
pub struct RawImage {
    pub width: usize,
    pub height: usize,
    pub pixels: Vec<Rgb>,
}
