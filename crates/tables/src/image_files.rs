//! Image files in memory: PNG (8/16-bit RGB, through `png`) and OpenEXR (half/float RGB,
//! through `exr`), and reading them back (`image`, `exr`). No timestamps: the bytes depend
//! only on the texels and the encoding.
//!
//! PNG colour chunks (PNG 3rd edition §11.3.2): the sRGB-encoded files carry `sRGB`
//! (perceptual intent) with the fallback `gAMA` 45455 and `cHRM` of sRGB; the linear files
//! carry `gAMA` 100000 (gamma 1.0: the samples are linear) and the same `cHRM` (Rec.709
//! primaries, D65 white), so a loader can tell linear from sRGB-encoded files.

use std::io::Cursor;

use anyhow::{bail, Context, Result};
use half::f16;

use crate::texel::{Encoding, Texels};

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
        Texels::U8(v) => png(encoding, v, width, height, png::BitDepth::Eight),
        // PNG stores 16-bit samples big-endian.
        Texels::U16(v) => {
            png(encoding, &v.iter().flat_map(|c| c.to_be_bytes()).collect::<Vec<u8>>(), width, height, png::BitDepth::Sixteen)
        }
        Texels::F16(v) => exr_rgb(width, height, |i| (v[i], v[i + 1], v[i + 2])),
        Texels::F32(v) => exr_rgb(width, height, |i| (v[i], v[i + 1], v[i + 2])),
    }
    .with_context(|| format!("encoding a {width}×{height} {} image", encoding.name()))
}

/// The PNG colour chunks of an encoding's files, in words (for the manifest).
pub fn png_color_chunks(encoding: Encoding) -> &'static str {
    if encoding == Encoding::Unorm8Srgb {
        "sRGB chunk (perceptual) with gAMA 45455 and cHRM of sRGB: sRGB-encoded samples"
    } else {
        "gAMA 100000 (gamma 1.0: linear samples) and cHRM Rec.709/sRGB primaries with D65 white"
    }
}

/// The colour chunks of every PNG, in words.
pub const PNG_CHUNKS_NOTE: &str = "unorm8-srgb PNGs carry an sRGB chunk (with the fallback gAMA 45455 and cHRM of sRGB); unorm8 and unorm16 PNGs carry gAMA 100000 (gamma 1.0, linear samples) and cHRM with the Rec.709/sRGB primaries and D65 white. A colour-managed loader therefore leaves the linear files' values as stored; a loader that ignores chunks must be told which files are linear (encodings[].color_space).";

/// The chromaticities of the cHRM chunk: D65 white, Rec.709 primaries (IEC 61966-2-1).
fn srgb_chromaticities() -> png::SourceChromaticities {
    use nklut_optics::color::srgb::{D65_CHROMATICITY, SRGB_PRIMARIES};
    let point = |(x, y): (f64, f64)| (x as f32, y as f32);
    png::SourceChromaticities::new(point(D65_CHROMATICITY), point(SRGB_PRIMARIES[0]), point(SRGB_PRIMARIES[1]), point(SRGB_PRIMARIES[2]))
}

fn png(encoding: Encoding, bytes: &[u8], width: usize, height: usize, depth: png::BitDepth) -> Result<Vec<u8>> {
    let mut out = Vec::new();
    let mut encoder = png::Encoder::new(&mut out, u32::try_from(width)?, u32::try_from(height)?);
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(depth);
    encoder.set_compression(png::Compression::Balanced);
    encoder.set_source_chromaticities(srgb_chromaticities());
    if encoding == Encoding::Unorm8Srgb {
        encoder.set_source_srgb(png::SrgbRenderingIntent::Perceptual);
        encoder.set_source_gamma(png::ScaledFloat::new(0.45455));
    } else {
        encoder.set_source_gamma(png::ScaledFloat::new(1.0));
    }
    let mut writer = encoder.write_header()?;
    writer.write_image_data(bytes)?;
    writer.finish()?;
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

#[cfg(test)]
mod tests {
    use super::*;

    /// The chunks of a PNG file in order: (type, data), read from the bytes by hand.
    fn chunks(bytes: &[u8]) -> Vec<(String, Vec<u8>)> {
        assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n");
        let mut chunks = Vec::new();
        let mut at = 8;
        while at < bytes.len() {
            let length = u32::from_be_bytes(bytes[at..at + 4].try_into().unwrap()) as usize;
            let kind = String::from_utf8(bytes[at + 4..at + 8].to_vec()).unwrap();
            chunks.push((kind, bytes[at + 8..at + 8 + length].to_vec()));
            at += 12 + length;
        }
        chunks
    }

    fn chunk<'a>(chunks: &'a [(String, Vec<u8>)], kind: &str) -> Option<&'a [u8]> {
        chunks.iter().find(|(k, _)| k == kind).map(|(_, d)| d.as_slice())
    }

    /// cHRM of sRGB: white, red, green, blue (x, y) × 100000, big-endian u32 each.
    fn srgb_chrm() -> Vec<u8> {
        [31270u32, 32900, 64000, 33000, 30000, 60000, 15000, 6000].iter().flat_map(|v| v.to_be_bytes()).collect()
    }

    #[test]
    fn png_files_say_whether_they_are_linear_or_srgb() {
        let texels8 = Texels::U8(vec![0, 128, 255, 10, 20, 30]);
        let srgb = chunks(&encode(Encoding::Unorm8Srgb, 2, 1, &texels8).unwrap());
        assert_eq!(chunk(&srgb, "sRGB"), Some(&[0u8][..])); // rendering intent 0 = perceptual
        assert_eq!(chunk(&srgb, "gAMA"), Some(&45455u32.to_be_bytes()[..]));
        assert_eq!(chunk(&srgb, "cHRM"), Some(&srgb_chrm()[..]));
        for (encoding, texels, depth) in
            [(Encoding::Unorm8, texels8.clone(), 8u8), (Encoding::Unorm16, Texels::U16(vec![0, 1, 65535, 256, 513, 40000]), 16)]
        {
            let bytes = encode(encoding, 2, 1, &texels).unwrap();
            let list = chunks(&bytes);
            assert_eq!(list[0].0, "IHDR");
            assert_eq!(list[0].1[8], depth, "{}", encoding.name());
            assert_eq!(chunk(&list, "sRGB"), None, "{}", encoding.name());
            assert_eq!(chunk(&list, "gAMA"), Some(&100_000u32.to_be_bytes()[..]), "{}", encoding.name());
            assert_eq!(chunk(&list, "cHRM"), Some(&srgb_chrm()[..]), "{}", encoding.name());
            // Colour chunks precede the image data, as PNG requires.
            let position = |kind: &str| list.iter().position(|(k, _)| k == kind).unwrap();
            assert!(position("gAMA") < position("IDAT") && position("cHRM") < position("IDAT"));
            // The samples survive the trip (16-bit big-endian in the file, values as given).
            assert_eq!(decode(encoding, &bytes).unwrap().texels, texels, "{}", encoding.name());
        }
    }
}
