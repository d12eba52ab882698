//! PNG output: an SVG plot rendered with `resvg` (text with the system fonts, when there are any).

use crate::errors::{Error, Result};
use resvg::{tiny_skia, usvg};
use std::sync::OnceLock;

fn options() -> &'static usvg::Options<'static> {
    static OPTIONS: OnceLock<usvg::Options<'static>> = OnceLock::new();
    OPTIONS.get_or_init(|| {
        let mut opt = usvg::Options::default();
        opt.fontdb_mut().load_system_fonts();
        opt
    })
}

/// Renders SVG text to PNG bytes of exactly `width` x `height` pixels (the drawing is scaled to fit).
pub fn svg_to_png(svg: &str, width: u32, height: u32) -> Result<Vec<u8>> {
    let tree = usvg::Tree::from_str(svg, options())
        .map_err(|e| Error::InvalidData(format!("SVG could not be parsed: {e}")))?;
    let mut pixmap = tiny_skia::Pixmap::new(width, height)
        .ok_or_else(|| Error::InvalidOption(format!("cannot render {width}x{height} pixels")))?;
    let sz = tree.size();
    let transform =
        tiny_skia::Transform::from_scale(width as f32 / sz.width(), height as f32 / sz.height());
    resvg::render(&tree, transform, &mut pixmap.as_mut());
    pixmap
        .encode_png()
        .map_err(|e| Error::InvalidData(format!("PNG encoding failed: {e}")))
}

/// Width and height read from a PNG's IHDR chunk; `None` if the bytes are not a PNG.
pub fn png_size(bytes: &[u8]) -> Option<(u32, u32)> {
    const SIG: [u8; 8] = [137, 80, 78, 71, 13, 10, 26, 10];
    if bytes.len() < 24 || bytes[..8] != SIG || &bytes[12..16] != b"IHDR" {
        return None;
    }
    let w = u32::from_be_bytes(bytes[16..20].try_into().ok()?);
    let h = u32::from_be_bytes(bytes[20..24].try_into().ok()?);
    Some((w, h))
}
