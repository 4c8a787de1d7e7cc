//! Frames a person can look at: the reference beside the distance-map renders, as linear
//! OpenEXR (float) and sRGB PNG, and a false-colour PNG of each render's error against the
//! reference; and signed maps (a per-pixel signed error, such as accessibility − reference)
//! in a diverging colour scale with its colour bar. Encoding through `bake::files` (the textures' encoders); the files join the
//! set of the command that made them (`output::publish_contents`), so frames of a killed
//! or earlier run never mix with this one's.

use anyhow::Result;

use super::trace::TracedFrame;
use nklut_optics::color::srgb;
use nklut_pipeline::bake::files::encode;
use nklut_pipeline::bake::texel::{Encoding, Texels};
use nklut_pipeline::output::SetFile;

/// One frame to show: a file stem, the frame and, for an error image, its reference.
#[derive(Clone, Debug)]
pub struct Picture {
    pub stem: String,
    pub frame: TracedFrame,
    pub reference: Option<TracedFrame>,
}

/// |Δ| summed over channels at which the false colour saturates (white).
pub const ERROR_SCALE: f64 = 0.1;

/// The false colour of an error e ≥ 0: black at 0, through blue, red and yellow, to white
/// at [`ERROR_SCALE`] and beyond (piecewise linear between those five stops).
pub fn false_colour(error: f64) -> [f64; 3] {
    const STOPS: [[f64; 3]; 5] = [[0.0, 0.0, 0.0], [0.1, 0.1, 0.8], [0.9, 0.1, 0.1], [1.0, 0.9, 0.1], [1.0, 1.0, 1.0]];
    let x = (error / ERROR_SCALE).clamp(0.0, 1.0) * (STOPS.len() - 1) as f64;
    let i = (x.floor() as usize).min(STOPS.len() - 2);
    let w = x - i as f64;
    std::array::from_fn(|c| STOPS[i][c] + w * (STOPS[i + 1][c] - STOPS[i][c]))
}

/// The signed error at which the diverging colour saturates (accessibility units).
pub const SIGNED_SCALE: f64 = 0.25;
/// The colour bar of the signed maps: −[`SIGNED_SCALE`] at the left, 0 in the middle.
pub const SIGNED_SCALE_FILE: &str = "signed_scale.png";
/// Where a signed map has no value (no surface): mid grey.
pub const NO_VALUE: [f64; 3] = [0.5, 0.5, 0.5];

/// The diverging colour of a signed error e: white at 0, to pure blue at −[`SIGNED_SCALE`]
/// and beyond (negative: too little accessibility, the surfels over-occlude), to pure red at
/// +[`SIGNED_SCALE`] (positive: they under-occlude); linear in between.
pub fn signed_colour(error: f64) -> [f64; 3] {
    let t = (error / SIGNED_SCALE).clamp(-1.0, 1.0);
    if t >= 0.0 {
        [1.0, 1.0 - t, 1.0 - t]
    } else {
        [1.0 + t, 1.0 + t, 1.0]
    }
}

/// A per-pixel signed error (`None`: nothing there) of `width` × `height` pixels.
#[derive(Clone, Debug, PartialEq)]
pub struct SignedMap {
    pub stem: String,
    pub width: u32,
    pub height: u32,
    pub values: Vec<Option<f64>>,
}

/// `<folder>/<stem>.png` per map in [`signed_colour`] ([`NO_VALUE`] where there is none)
/// and, with any map, the colour bar `<folder>/signed_scale.png` (256 × 16, −scale … +scale).
pub fn signed_files(folder: &str, maps: &[SignedMap]) -> Result<Vec<SetFile>> {
    let mut written = Vec::new();
    for map in maps {
        let colours = map.values.iter().map(|v| v.map_or(NO_VALUE, signed_colour));
        written.push(SetFile::new(format!("{folder}/{}.png", map.stem), error_png(map.width, map.height, colours)?));
    }
    if !maps.is_empty() {
        let bar: Vec<[f64; 3]> = (0..16).flat_map(|_| (0..256).map(|x| signed_colour(SIGNED_SCALE * (x as f64 - 127.5) / 127.5))).collect();
        written.push(SetFile::new(format!("{folder}/{SIGNED_SCALE_FILE}"), error_png(256, 16, bar.into_iter())?));
    }
    Ok(written)
}

/// |Δ| summed over the channels, per pixel: what an error image shows in false colour.
pub fn error_map(frame: &TracedFrame, reference: &TracedFrame) -> Vec<f64> {
    frame.radiance.iter().zip(&reference.radiance).map(|(a, r)| (0..3).map(|c| (a[c] - r[c]).abs()).sum()).collect()
}

/// A PNG of linear radiance, sRGB-encoded.
pub fn srgb_png(width: u32, height: u32, linear: impl Iterator<Item = [f64; 3]>) -> Result<Vec<u8>> {
    let bytes = linear.flat_map(srgb::srgb8).collect();
    encode(Encoding::Unorm8Srgb, width as usize, height as usize, &Texels::U8(bytes))
}

/// A PNG of false colours ([`false_colour`]), stored as they are: they are display-referred.
pub fn error_png(width: u32, height: u32, colours: impl Iterator<Item = [f64; 3]>) -> Result<Vec<u8>> {
    let bytes = colours.flat_map(|rgb| rgb.map(|v| (v * 255.0).round() as u8)).collect();
    encode(Encoding::Unorm8, width as usize, height as usize, &Texels::U8(bytes))
}

/// The files `<folder>/<stem>.exr` (linear) and `<stem>.png` (sRGB) per picture, and for a
/// picture with a reference `<stem>_error.png` (false colour of |Δ| summed over channels).
pub fn files(folder: &str, pictures: &[Picture]) -> Result<Vec<SetFile>> {
    let mut written = Vec::new();
    for picture in pictures {
        let frame = &picture.frame;
        let (w, h) = (frame.width, frame.height);
        let linear = Texels::F32(frame.radiance.iter().flat_map(|rgb| rgb.map(|v| v as f32)).collect());
        let mut files = vec![(format!("{}.exr", picture.stem), encode(Encoding::F32, w as usize, h as usize, &linear)?)];
        files.push((format!("{}.png", picture.stem), srgb_png(w, h, frame.radiance.iter().copied())?));
        if let Some(reference) = &picture.reference {
            let errors = error_map(frame, reference).into_iter().map(false_colour);
            files.push((format!("{}_error.png", picture.stem), error_png(w, h, errors)?));
        }
        written.extend(files.into_iter().map(|(name, bytes)| SetFile::new(format!("{folder}/{name}"), bytes)));
    }
    Ok(written)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn false_colour_runs_from_black_to_white_through_its_stops() {
        assert_eq!(false_colour(0.0), [0.0; 3]);
        assert_eq!(false_colour(-1.0), [0.0; 3]);
        assert_eq!(false_colour(ERROR_SCALE), [1.0; 3]);
        assert_eq!(false_colour(5.0), [1.0; 3]);
        // Halfway: the middle stop (red).
        assert_eq!(false_colour(ERROR_SCALE / 2.0), [0.9, 0.1, 0.1]);
        // An eighth: halfway between black and blue.
        let eighth = false_colour(ERROR_SCALE / 8.0);
        assert!((eighth[2] - 0.4).abs() < 1e-12 && (eighth[0] - 0.05).abs() < 1e-12);
    }

    /// White at 0, pure red at +scale, pure blue at −scale, half-way between: half-tinted.
    #[test]
    fn signed_colour_diverges_from_white() {
        assert_eq!(signed_colour(0.0), [1.0; 3]);
        assert_eq!(signed_colour(SIGNED_SCALE), [1.0, 0.0, 0.0]);
        assert_eq!(signed_colour(3.0), [1.0, 0.0, 0.0]);
        assert_eq!(signed_colour(-SIGNED_SCALE), [0.0, 0.0, 1.0]);
        assert_eq!(signed_colour(SIGNED_SCALE / 2.0), [1.0, 0.5, 0.5]);
        assert_eq!(signed_colour(-SIGNED_SCALE / 4.0), [0.75, 0.75, 1.0]);
        let map = SignedMap { stem: "s".into(), width: 3, height: 1, values: vec![Some(SIGNED_SCALE), None, Some(-SIGNED_SCALE)] };
        let written = signed_files("f", &[map]).unwrap();
        assert_eq!(written.iter().map(|f| f.name.as_str()).collect::<Vec<_>>(), ["f/s.png", "f/signed_scale.png"]);
        let decoded = nklut_pipeline::bake::files::decode(Encoding::Unorm8, &written[0].bytes).unwrap();
        assert_eq!(decoded.texels, Texels::U8(vec![255, 0, 0, 128, 128, 128, 0, 0, 255]));
        assert!(signed_files("f", &[]).unwrap().is_empty());
    }

    #[test]
    fn pictures_are_written_as_exr_png_and_error_png() {
        let frame =
            TracedFrame { width: 2, height: 1, radiance: vec![[0.5, 0.25, 1.0], [0.0, 0.0, 0.0]], seen: vec![Some(0), None], rays: 2 };
        let mut other = frame.clone();
        other.radiance[0][0] = 0.6;
        let written = files(
            "f",
            &[
                Picture { stem: "reference".into(), frame: frame.clone(), reference: None },
                Picture { stem: "schlick".into(), frame: other, reference: Some(frame) },
            ],
        )
        .unwrap();
        let names: Vec<&str> = written.iter().map(|f| f.name.as_str()).collect();
        assert_eq!(names, ["f/reference.exr", "f/reference.png", "f/schlick.exr", "f/schlick.png", "f/schlick_error.png"]);
        let bytes = |name: &str| written.iter().find(|f| f.name == name).unwrap().bytes.clone();
        let decoded = nklut_pipeline::bake::files::decode(Encoding::F32, &bytes("f/schlick.exr")).unwrap();
        assert_eq!(decoded.texels, Texels::F32(vec![0.6, 0.25, 1.0, 0.0, 0.0, 0.0]));
        let error = nklut_pipeline::bake::files::decode(Encoding::Unorm8, &bytes("f/schlick_error.png")).unwrap();
        // |Δ| = 0.1 at the first pixel: white; none at the second: black.
        assert_eq!(error.texels, Texels::U8(vec![255, 255, 255, 0, 0, 0]));
    }
}
