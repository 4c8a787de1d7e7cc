//! Frames a person can look at: the reference beside the distance-map renders, as linear
//! OpenEXR (float) and sRGB PNG, and a false-colour PNG of each render's error against the
//! reference. Encoding through `bake::files` (the textures' encoders); the files join the
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
