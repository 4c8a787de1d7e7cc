//! Image files in memory: PNG (8/16-bit RGB, through `image`) and OpenEXR (half/float RGB,
//! through `exr`), and reading them back with the same crates. No colour chunks, no
//! timestamps: the bytes depend only on the texels.

use std::io::Cursor;

use anyhow::{bail, Context, Result};
use half::f16;
use image::codecs::png::{CompressionType, FilterType, PngEncoder};
use image::{ExtendedColorType, ImageEncoder};

use super::texel::{Encoding, Texels};

/// The pixels of one image read back from its file.
#[derive(Clone, Debug, PartialEq)]
pub struct Decoded {
    pub width: usize,
    pub height: usize,
    pub texels: Texels,
}

/// Encode `width` × `height` RGB texels (interleaved, row-major, first row on top) as the
/// file format of `encoding`: PNG for unorm, EXR (ZIP16, increasing line order) for floats.
pub fn encode(encoding: Encoding, width: usize, height: usize, texels: &Texels) -> Result<Vec<u8>> {
    if width == 0 || height == 0 || texels.len() != 3 * width * height {
        bail!("{width}×{height} RGB image needs {} values, got {}", 3 * width * height, texels.len());
    }
    match texels {
        Texels::U8(v) => png(v, width, height, ExtendedColorType::Rgb8),
        Texels::U16(v) => png(&v.iter().flat_map(|c| c.to_ne_bytes()).collect::<Vec<u8>>(), width, height, ExtendedColorType::Rgb16),
        Texels::F16(v) => exr_rgb(width, height, |i| (v[i], v[i + 1], v[i + 2])),
        Texels::F32(v) => exr_rgb(width, height, |i| (v[i], v[i + 1], v[i + 2])),
    }
    .with_context(|| format!("encoding a {width}×{height} {} image", encoding.name()))
}

fn png(bytes: &[u8], width: usize, height: usize, color: ExtendedColorType) -> Result<Vec<u8>> {
    let mut out = Vec::new();
    PngEncoder::new_with_quality(&mut out, CompressionType::Default, FilterType::Adaptive).write_image(
        bytes,
        u32::try_from(width)?,
        u32::try_from(height)?,
        color,
    )?;
    Ok(out)
}

fn exr_rgb<S>(width: usize, height: usize, texel: impl Fn(usize) -> (S, S, S) + Sync) -> Result<Vec<u8>>
where
    S: exr::prelude::IntoSample,
{
    use exr::prelude::{Blocks, Compression, Image, LineOrder, SpecificChannels, Vec2, WritableImage};
    let encoding = exr::prelude::Encoding { compression: Compression::ZIP16, blocks: Blocks::ScanLines, line_order: LineOrder::Increasing };
    let channels = SpecificChannels::rgb(|p: Vec2<usize>| texel(3 * (p.y() * width + p.x())));
    let image = Image::from_encoded_channels((width, height), encoding, channels);
    let mut out = Cursor::new(Vec::new());
    image.write().non_parallel().to_buffered(&mut out).map_err(|e| anyhow::anyhow!("{e}"))?;
    Ok(out.into_inner())
}

/// Read a file written by `encode` back into texels of `encoding`'s type.
pub fn decode(encoding: Encoding, bytes: &[u8]) -> Result<Decoded> {
    if encoding.is_float() {
        decode_exr(encoding, bytes)
    } else {
        decode_png(encoding, bytes)
    }
}

fn decode_png(encoding: Encoding, bytes: &[u8]) -> Result<Decoded> {
    let image = image::load_from_memory_with_format(bytes, image::ImageFormat::Png)?;
    let (width, height) = (image.width() as usize, image.height() as usize);
    let texels = match (encoding, image) {
        (Encoding::Unorm8 | Encoding::Unorm8Srgb, image::DynamicImage::ImageRgb8(i)) => Texels::U8(i.into_raw()),
        (Encoding::Unorm16, image::DynamicImage::ImageRgb16(i)) => Texels::U16(i.into_raw()),
        (_, other) => bail!("PNG holds {:?}, not the RGB layout of {}", other.color(), encoding.name()),
    };
    Ok(Decoded { width, height, texels })
}

fn decode_exr(encoding: Encoding, bytes: &[u8]) -> Result<Decoded> {
    use exr::prelude::{read, ReadChannels, ReadLayers, SampleType};
    let meta = exr::meta::MetaData::read_from_buffered(Cursor::new(bytes), false).map_err(|e| anyhow::anyhow!("{e}"))?;
    let want = if encoding == Encoding::F16 { SampleType::F16 } else { SampleType::F32 };
    let header = meta.headers.first().context("EXR without a layer")?;
    if header.channels.list.iter().any(|c| c.sample_type != want) {
        bail!("EXR channels are not all {want:?}");
    }
    let image = read()
        .no_deep_data()
        .largest_resolution_level()
        .rgb_channels(
            |size, _| (size.width(), vec![0.0f32; 3 * size.area()]),
            |(width, pixels), p, (r, g, b): (f32, f32, f32)| {
                let i = 3 * (p.y() * *width + p.x());
                pixels[i..i + 3].copy_from_slice(&[r, g, b]);
            },
        )
        .first_valid_layer()
        .all_attributes()
        .non_parallel()
        .from_buffered(Cursor::new(bytes))
        .map_err(|e| anyhow::anyhow!("{e}"))?;
    let size = image.layer_data.size;
    let (_, values) = image.layer_data.channel_data.pixels;
    let texels = match encoding {
        Encoding::F16 => Texels::F16(values.into_iter().map(f16::from_f32).collect()),
        _ => Texels::F32(values),
    };
    Ok(Decoded { width: size.width(), height: size.height(), texels })
}
