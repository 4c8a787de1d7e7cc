//! Hero frames: one camera frame of a scene at a size a person looks at (its long side
//! [`DEFAULT_HERO_SIZE`] pixels unless asked otherwise), the reference beside every variant
//! the scene compares (each Fresnel method through the distance maps; no AO and each pass
//! count of surfel AO), each variant's error image on one stated scale, and crops of the
//! window where the error is largest. Written under [`HERO_DIR`] with the `effects_hero`
//! table (one row per panel: what it shows, its files, its error figures), which the
//! report lays out; the figures are [`crate::image_error`]'s, the false colour
//! [`crate::colour_bar::false_colour`]'s.
//!
//! Reflections and refractions carry two error images per method: against the exact
//! method's panel through the same distance maps (what the Fresnel method itself costs) and
//! against the ray-traced reference (the total, the maps' search included). Each kind is
//! drawn on one scale for all the set's panels, chosen by [`crate::colour_bar`]'s rule (the
//! 1-2-5 step at or above the 99th percentile of the values over the pixels the figures
//! count), with its legend ([`crate::colour_bar::legend_png`]) beside the pictures. The
//! ambient-occlusion set (every pixel counted) has one such scale over its panels against
//! the reference.
//!
//! The crop window is the square of a quarter of the frame's long side whose summed error
//! (|Δ| over R, G and B) is largest in the panel with the largest mean error, searched on a
//! grid of an eighth of the window through a summed-area table; every panel is cropped at
//! the same window, so crops compare like with like.

use anyhow::Result;
use nklut_tables::effects_tables::effects_hero;

use super::colour_bar::{self, error_png, p99_scale};
use super::distance_map::Configuration;
use super::image_error::{compare, compare_all, FrameError};
use super::pictures::{error_map, srgb_png};
use super::trace::TracedFrame;
use crate::scene::EffectFamily;
use nklut_tables::output::{SetFile, Table};

/// The folder of the hero files in the effects' set.
pub const HERO_DIR: &str = "effects_hero";
/// The long side of a hero frame in pixels unless asked otherwise (`--hero-size`).
pub const DEFAULT_HERO_SIZE: u32 = 512;
/// The width of a legend of a scaled set (colour bar, values, meaning).
pub const LEGEND_WIDTH: u32 = 512;
/// The method whose panel the others are compared with for the Fresnel method's own error.
pub const EXACT_METHOD: &str = "exact";

/// The hero frame's size: the scene's aspect ratio with its long side `long_side` pixels
/// (the short side rounded, at least 1).
pub fn hero_resolution([width, height]: [u32; 2], long_side: u32) -> [u32; 2] {
    let scaled = |short: u32, long: u32| ((f64::from(short) * f64::from(long_side) / f64::from(long.max(1))).round() as u32).max(1);
    if width >= height {
        [long_side, scaled(height, width)]
    } else {
        [scaled(width, height), long_side]
    }
}

/// The words a table and a page use for a family.
pub fn family_label(family: EffectFamily) -> &'static str {
    match family {
        EffectFamily::SpecularPaths => "reflections and refractions",
        EffectFamily::Surfels => "ambient occlusion",
    }
}

fn family_stem(family: EffectFamily) -> &'static str {
    match family {
        EffectFamily::SpecularPaths => "specular",
        EffectFamily::Surfels => "ao",
    }
}

/// Over which pixels a panel's error figures are taken.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ErrorMask {
    /// Where the reference shows a specular object (what the Fresnel methods change).
    SpecularObjects,
    /// Every pixel.
    Whole,
}

/// One variant of a hero frame.
#[derive(Clone, Debug)]
pub struct HeroPanel {
    /// File stem within the set (`schlick`, `passes2_tree`).
    pub stem: String,
    /// What a reader sees under the picture.
    pub label: String,
    /// The Fresnel method or AO variant.
    pub method: String,
    /// Depths and search of a distance-map panel.
    pub configuration: Option<Configuration>,
    /// Accessibility passes of an AO panel (0: no AO).
    pub passes: Option<u32>,
    pub frame: TracedFrame,
}

/// A family's hero frame: the reference and the variants, all at one size.
#[derive(Clone, Debug)]
pub struct HeroSet {
    pub effect: EffectFamily,
    pub reference_label: String,
    pub reference: TracedFrame,
    pub panels: Vec<HeroPanel>,
    pub mask: ErrorMask,
}

/// A square of the frame, in pixels from its top left.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Window {
    pub x: u32,
    pub y: u32,
    pub size: u32,
}

/// One row of `effects_hero`: a panel and its files.
#[derive(Clone, Debug, PartialEq)]
pub struct HeroRow {
    pub effect: EffectFamily,
    pub panel: String,
    pub label: String,
    pub method: String,
    pub configuration: Option<Configuration>,
    pub passes: Option<u32>,
    pub resolution: [u32; 2],
    pub file: String,
    /// The error image (none for the reference).
    pub error_file: Option<String>,
    pub crop: Window,
    pub crop_file: String,
    pub crop_error_file: Option<String>,
    pub error: FrameError,
    /// |Δ| summed over R, G, B at which the error image is white.
    pub error_scale: f64,
    /// The legend of the error image (colour bar with its values).
    pub error_scale_file: String,
    /// Against the exact method's panel (reflections and refractions, every method but
    /// exact): the error image, its crop, the figures and the scale of its legend.
    pub exact: Option<ExactComparison>,
}

/// A panel against the exact method's panel at the same depths and search.
#[derive(Clone, Debug, PartialEq)]
pub struct ExactComparison {
    pub error_file: String,
    pub crop_error_file: String,
    pub error: FrameError,
    pub scale: f64,
    pub scale_file: String,
}

/// The `size`-pixel square with the largest sum of `values` (row-major, `width` × `height`),
/// on a grid of `size / 8` pixels (the window clamped into the frame; ties: the first in
/// reading order).
pub fn worst_window(values: &[f64], width: u32, height: u32, size: u32) -> Window {
    let size = size.clamp(1, width.min(height).max(1));
    let (w, h) = (width as usize, height as usize);
    // table[y][x] = sum of values above and left of (x, y), one row and column of zeros.
    let mut table = vec![0.0f64; (w + 1) * (h + 1)];
    for y in 0..h {
        let mut row = 0.0;
        for x in 0..w {
            row += values[y * w + x];
            table[(y + 1) * (w + 1) + x + 1] = table[y * (w + 1) + x + 1] + row;
        }
    }
    let at = |x: usize, y: usize| table[y * (w + 1) + x];
    let s = size as usize;
    let stride = (s / 8).max(1);
    let mut best = (f64::NEG_INFINITY, Window { x: 0, y: 0, size });
    let last = |extent: usize| extent.saturating_sub(s);
    let positions = |extent: usize| (0..=last(extent)).step_by(stride).chain(std::iter::once(last(extent)));
    for y in positions(h) {
        for x in positions(w) {
            let sum = at(x + s, y + s) - at(x, y + s) - at(x + s, y) + at(x, y);
            if sum > best.0 {
                best = (sum, Window { x: x as u32, y: y as u32, size });
            }
        }
    }
    best.1
}

/// The pixels of `window` of a `width`-wide row-major image.
fn crop<T: Copy>(values: &[T], width: u32, window: Window) -> Vec<T> {
    let (x, y, s, w) = (window.x as usize, window.y as usize, window.size as usize, width as usize);
    (y..y + s).flat_map(|row| values[row * w + x..row * w + x + s].iter().copied()).collect()
}

/// The values a set's error images show over the pixels its figures count: where the
/// reference shows a specular object, or every pixel.
fn counted<'a>(set: &'a HeroSet, values: &'a [f64]) -> impl Iterator<Item = f64> + 'a {
    values.iter().zip(&set.reference.seen).filter(|(_, seen)| set.mask == ErrorMask::Whole || seen.is_some()).map(|(v, _)| *v)
}

/// `frame`'s figures against `against`, over the pixels of the set's mask (the reference's
/// specular objects, or all).
fn figures_against(set: &HeroSet, frame: &TracedFrame, against: &TracedFrame) -> FrameError {
    let masked = TracedFrame { seen: set.reference.seen.clone(), ..against.clone() };
    match set.mask {
        ErrorMask::SpecularObjects => compare(frame, &masked),
        ErrorMask::Whole => compare_all(frame, &masked),
    }
}

/// The files of every hero set under [`HERO_DIR`] (with the legends) and the rows of
/// `effects_hero`.
pub fn files(sets: &[HeroSet]) -> Result<(Vec<SetFile>, Vec<HeroRow>)> {
    let mut written = Vec::new();
    let mut rows = Vec::new();
    for set in sets {
        let (width, height) = (set.reference.width, set.reference.height);
        let errors: Vec<Vec<f64>> = set.panels.iter().map(|p| error_map(&p.frame, &set.reference)).collect();
        let figures: Vec<FrameError> = set.panels.iter().map(|p| figures_against(set, &p.frame, &set.reference)).collect();
        let worst = figures.iter().enumerate().max_by(|a, b| a.1.mean_absolute.total_cmp(&b.1.mean_absolute)).map(|(i, _)| i);
        let window_size = (width.max(height) / 4).max(1);
        let window = match worst {
            Some(i) => worst_window(&errors[i], width, height, window_size),
            None => worst_window(&vec![0.0; (width * height) as usize], width, height, window_size),
        };
        let prefix = family_stem(set.effect);
        let mut put = |name: String, bytes: Vec<u8>| {
            let path = format!("{HERO_DIR}/{name}");
            written.push(SetFile::new(path.clone(), bytes));
            path
        };
        // The scales, by the rule: one over every panel against the reference, and for
        // reflections and refractions one over every panel against exact.
        let exact = set.panels.iter().find(|p| p.method == EXACT_METHOD).filter(|_| set.mask == ErrorMask::SpecularObjects);
        let exact_errors: Vec<Option<Vec<f64>>> =
            set.panels.iter().map(|p| exact.filter(|_| p.method != EXACT_METHOD).map(|e| error_map(&p.frame, &e.frame))).collect();
        let scale = p99_scale(errors.iter().flat_map(|e| counted(set, e)));
        let legend = colour_bar::legend_png(LEGEND_WIDTH, scale, "|panel - reference| summed over R, G, B")?;
        let scale_file = put(format!("{prefix}_error_scale.png"), legend);
        let exact_scale = match exact_errors.iter().flatten().next() {
            Some(_) => {
                let scale = p99_scale(exact_errors.iter().flatten().flat_map(|e| counted(set, e)));
                let legend = colour_bar::legend_png(LEGEND_WIDTH, scale, "|panel - exact panel| summed over R, G, B")?;
                Some((scale, put(format!("{prefix}_exact_error_scale.png"), legend)))
            }
            None => None,
        };
        let colours = |values: &[f64], scale: f64| values.iter().map(|&v| colour_bar::colour(v, scale)).collect::<Vec<_>>();
        let reference_rgb = srgb_png(width, height, set.reference.radiance.iter().copied())?;
        let reference_crop = srgb_png(window.size, window.size, crop(&set.reference.radiance, width, window).into_iter())?;
        rows.push(HeroRow {
            effect: set.effect,
            panel: "reference".into(),
            label: set.reference_label.clone(),
            method: "reference".into(),
            configuration: set.panels.first().and_then(|p| p.configuration),
            passes: None,
            resolution: [width, height],
            file: put(format!("{prefix}_reference.png"), reference_rgb),
            error_file: None,
            crop: window,
            crop_file: put(format!("{prefix}_reference_crop.png"), reference_crop),
            crop_error_file: None,
            error: compare_all(&set.reference, &set.reference),
            error_scale: scale,
            error_scale_file: scale_file.clone(),
            exact: None,
        });
        for ((panel, error), (figure, exact_error)) in set.panels.iter().zip(&errors).zip(figures.into_iter().zip(&exact_errors)) {
            let stem = format!("{prefix}_{}", panel.stem);
            let picture = srgb_png(width, height, panel.frame.radiance.iter().copied())?;
            let error_picture = error_png(width, height, colours(error, scale).into_iter())?;
            let picture_crop = srgb_png(window.size, window.size, crop(&panel.frame.radiance, width, window).into_iter())?;
            let error_crop = error_png(window.size, window.size, colours(&crop(error, width, window), scale).into_iter())?;
            let against_exact = match (exact_error, exact, &exact_scale) {
                (Some(values), Some(exact), Some((scale, scale_file))) => Some(ExactComparison {
                    error_file: put(format!("{stem}_exact_error.png"), error_png(width, height, colours(values, *scale).into_iter())?),
                    crop_error_file: put(
                        format!("{stem}_crop_exact_error.png"),
                        error_png(window.size, window.size, colours(&crop(values, width, window), *scale).into_iter())?,
                    ),
                    error: figures_against(set, &panel.frame, &exact.frame),
                    scale: *scale,
                    scale_file: scale_file.clone(),
                }),
                _ => None,
            };
            rows.push(HeroRow {
                effect: set.effect,
                panel: panel.stem.clone(),
                label: panel.label.clone(),
                method: panel.method.clone(),
                configuration: panel.configuration,
                passes: panel.passes,
                resolution: [width, height],
                file: put(format!("{stem}.png"), picture),
                error_file: Some(put(format!("{stem}_error.png"), error_picture)),
                crop: window,
                crop_file: put(format!("{stem}_crop.png"), picture_crop),
                crop_error_file: Some(put(format!("{stem}_crop_error.png"), error_crop)),
                error: figure,
                error_scale: scale,
                error_scale_file: scale_file.clone(),
                exact: against_exact,
            });
        }
    }
    Ok((written, rows))
}

/// The `effects_hero` table of `rows`.
pub fn hero_table(rows: &[HeroRow]) -> Table {
    let text = |f: &dyn Fn(&HeroRow) -> String| rows.iter().map(f).collect::<Vec<_>>();
    let optional_text = |f: &dyn Fn(&HeroRow) -> Option<String>| rows.iter().map(|r| f(r).unwrap_or_default()).collect::<Vec<_>>();
    let integer = |f: &dyn Fn(&HeroRow) -> i64| rows.iter().map(f).collect::<Vec<_>>();
    // Integers that a panel may lack, as optional floats (written as integers: "3").
    let configuration =
        |f: &dyn Fn(&Configuration) -> u32| rows.iter().map(|r| r.configuration.map(|c| f64::from(f(&c)))).collect::<Vec<_>>();
    let mut table = Table::new();
    table
        .put(effects_hero::EFFECT, text(&|r| family_label(r.effect).into()))
        .put(effects_hero::PANEL, text(&|r| r.panel.clone()))
        .put(effects_hero::LABEL, text(&|r| r.label.clone()))
        .put(effects_hero::METHOD, text(&|r| r.method.clone()))
        .put(effects_hero::REFLECTION_DEPTH, configuration(&|c| c.depths.reflection))
        .put(effects_hero::REFRACTION_DEPTH, configuration(&|c| c.depths.refraction))
        .put(effects_hero::LINEAR_STEPS, configuration(&|c| c.steps.linear))
        .put(effects_hero::SECANT_STEPS, configuration(&|c| c.steps.secant))
        .put(effects_hero::PASSES, rows.iter().map(|r| r.passes.map(f64::from)).collect())
        .put(effects_hero::RESOLUTION, text(&|r| format!("{}x{}", r.resolution[0], r.resolution[1])))
        .put(effects_hero::FILE, text(&|r| r.file.clone()))
        .put(effects_hero::ERROR_FILE, optional_text(&|r| r.error_file.clone()))
        .put(effects_hero::CROP_X, integer(&|r| r.crop.x as i64))
        .put(effects_hero::CROP_Y, integer(&|r| r.crop.y as i64))
        .put(effects_hero::CROP_SIZE, integer(&|r| r.crop.size as i64))
        .put(effects_hero::CROP_FILE, text(&|r| r.crop_file.clone()))
        .put(effects_hero::CROP_ERROR_FILE, optional_text(&|r| r.crop_error_file.clone()))
        .put(effects_hero::PIXELS, integer(&|r| r.error.pixels as i64))
        .put(effects_hero::MEAN_ABS_ERROR, rows.iter().map(|r| r.error.mean_absolute).collect())
        .put(effects_hero::MAX_ABS_ERROR, rows.iter().map(|r| r.error.max_absolute).collect())
        .put(effects_hero::MEAN_DELTA_E2000, rows.iter().map(|r| r.error.mean_delta_e2000).collect())
        .put(effects_hero::MEAN_REL_ERROR, rows.iter().map(|r| r.error.mean_relative).collect())
        .put(effects_hero::ERROR_SCALE, rows.iter().map(|r| r.error_scale).collect())
        .put(effects_hero::ERROR_SCALE_FILE, text(&|r| r.error_scale_file.clone()))
        .put(effects_hero::EXACT_ERROR_FILE, optional_text(&|r| r.exact.as_ref().map(|e| e.error_file.clone())))
        .put(effects_hero::CROP_EXACT_ERROR_FILE, optional_text(&|r| r.exact.as_ref().map(|e| e.crop_error_file.clone())))
        .put(effects_hero::EXACT_MEAN_DELTA_E2000, rows.iter().map(|r| r.exact.as_ref().map(|e| e.error.mean_delta_e2000)).collect())
        .put(effects_hero::EXACT_MEAN_ABS_ERROR, rows.iter().map(|r| r.exact.as_ref().map(|e| e.error.mean_absolute)).collect())
        .put(effects_hero::EXACT_MAX_ABS_ERROR, rows.iter().map(|r| r.exact.as_ref().map(|e| e.error.max_absolute)).collect())
        .put(effects_hero::EXACT_ERROR_SCALE, rows.iter().map(|r| r.exact.as_ref().map(|e| e.scale)).collect())
        .put(effects_hero::EXACT_ERROR_SCALE_FILE, optional_text(&|r| r.exact.as_ref().map(|e| e.scale_file.clone())));
    table
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hero_sizes_keep_the_aspect_ratio() {
        assert_eq!(hero_resolution([128, 128], 512), [512, 512]);
        assert_eq!(hero_resolution([160, 90], 512), [512, 288]);
        assert_eq!(hero_resolution([90, 160], 512), [288, 512]);
        assert_eq!(hero_resolution([1000, 1], 512), [512, 1]);
    }

    #[test]
    fn the_worst_window_is_where_the_error_sits() {
        // 16 × 12 zeros with a 3 × 3 block of ones at x 9–11, y 5–7. An 8-pixel window (grid
        // of 1 pixel) covers it wholly for x in 4..=8 and y in 0..=4 (x + 8 > 11, x ≤ 16 − 8;
        // y + 8 > 7, y ≤ 12 − 8): the first in reading order is (4, 0).
        let (w, h) = (16u32, 12u32);
        let mut values = vec![0.0; (w * h) as usize];
        for y in 5..8 {
            for x in 9..12 {
                values[(y * w + x) as usize] = 1.0;
            }
        }
        let window = worst_window(&values, w, h, 8);
        assert_eq!(window, Window { x: 4, y: 0, size: 8 });
        let inside: f64 = crop(&values, w, window).iter().sum();
        assert_eq!(inside, 9.0);
        // A single hot pixel in the far corner: the window is clamped into the frame.
        let mut corner = vec![0.0; (w * h) as usize];
        corner[(w * h - 1) as usize] = 5.0;
        assert_eq!(worst_window(&corner, w, h, 8), Window { x: 8, y: 4, size: 8 });
    }

    #[test]
    fn panels_are_cropped_where_the_worst_one_errs() {
        let frame = |value: f64| TracedFrame { width: 8, height: 8, radiance: vec![[value; 3]; 64], seen: vec![Some(0); 64], rays: 64 };
        let reference = frame(0.5);
        let mut bad = frame(0.5);
        bad.radiance[7 * 8 + 7] = [0.6, 0.5, 0.5];
        let set = HeroSet {
            effect: EffectFamily::SpecularPaths,
            reference_label: "reference".into(),
            reference: reference.clone(),
            panels: vec![
                HeroPanel {
                    stem: "exact".into(),
                    label: "exact".into(),
                    method: "exact".into(),
                    configuration: None,
                    passes: None,
                    frame: frame(0.5),
                },
                HeroPanel {
                    stem: "schlick".into(),
                    label: "schlick".into(),
                    method: "schlick".into(),
                    configuration: None,
                    passes: None,
                    frame: bad,
                },
            ],
            mask: ErrorMask::SpecularObjects,
        };
        let (written, rows) = files(&[set]).unwrap();
        assert_eq!(rows.len(), 3);
        assert!(rows.iter().all(|r| r.crop == Window { x: 6, y: 6, size: 2 }), "{:?}", rows[0].crop);
        assert!((rows[2].error.max_absolute - 0.1).abs() < 1e-12, "{:?}", rows[2].error);
        assert_eq!(rows[1].error.mean_absolute, 0.0);
        let names: Vec<&str> = written.iter().map(|f| f.name.as_str()).collect();
        assert!(
            names.contains(&"effects_hero/specular_schlick_crop_error.png") && names.contains(&"effects_hero/specular_error_scale.png"),
            "{names:?}"
        );
        assert_eq!(hero_table(&rows).rows(), 3);
    }

    /// The ambient-occlusion set takes the same rule over every pixel: two pass counts off
    /// the reference by 0.03 and 0.02 in red on all 100 pixels (the background counted, no
    /// pixel specular): the 99th percentile of the 200 values is 0.03 → scale 0.05, with its
    /// legend beside the pictures.
    #[test]
    fn the_ambient_occlusion_set_takes_the_step_above_its_99th_percentile() {
        let frame =
            |red: f64| TracedFrame { width: 10, height: 10, radiance: vec![[red, 0.5, 0.5]; 100], seen: vec![None; 100], rays: 100 };
        let panel = |passes: u32, red: f64| HeroPanel {
            stem: format!("passes{passes}"),
            label: format!("{passes} passes"),
            method: "surfels".into(),
            configuration: None,
            passes: Some(passes),
            frame: frame(red),
        };
        let set = HeroSet {
            effect: EffectFamily::Surfels,
            reference_label: "reference".into(),
            reference: frame(0.5),
            panels: vec![panel(1, 0.53), panel(2, 0.52)],
            mask: ErrorMask::Whole,
        };
        let (written, rows) = files(&[set]).unwrap();
        assert!(rows.iter().all(|r| r.error_scale == 0.05 && r.error_scale_file == "effects_hero/ao_error_scale.png"), "{rows:?}");
        assert!(written.iter().any(|f| f.name == "effects_hero/ao_error_scale.png"));
        // The figures are per channel: 0.03 in one channel of three.
        assert!((rows[1].error.mean_absolute - 0.01).abs() < 1e-12, "{:?}", rows[1].error);
    }

    /// Two methods and the reference on 10 × 10 frames, every pixel specular: exact is off
    /// the reference by 0.01 in red everywhere; schlick by 0.01 in red and a further 0.03
    /// in green on 50 pixels, and 0.9 in blue on one. Against the reference the 200 values
    /// sorted are 100 × 0.01, 50 × 0.01 (schlick's plain pixels), 49 × 0.04, one 0.91: the
    /// 99th percentile at position 0.99 × 199 = 197.01 lies among the 0.04s → scale 0.05.
    /// Against exact (schlick only): 50 zeros, 49 × 0.03, one 0.9: position 0.99 × 99 =
    /// 98.01 between the last 0.03 and the 0.9 → 0.0387 → 0.05. The pictures are coloured on those scales: a 0.04 pixel at 0.8 of the way
    /// (between yellow and white), the outlier white; exact has no against-exact image.
    #[test]
    fn error_images_take_the_step_above_their_99th_percentile() {
        let frame =
            |value: [f64; 3]| TracedFrame { width: 10, height: 10, radiance: vec![value; 100], seen: vec![Some(0); 100], rays: 100 };
        let reference = frame([0.5; 3]);
        let exact = frame([0.51, 0.5, 0.5]);
        let mut schlick = exact.clone();
        for i in 0..49 {
            schlick.radiance[i][1] = 0.53;
        }
        schlick.radiance[99][2] = 1.4;
        let panel = |method: &str, frame: TracedFrame| HeroPanel {
            stem: method.into(),
            label: method.into(),
            method: method.into(),
            configuration: None,
            passes: None,
            frame,
        };
        let set = HeroSet {
            effect: EffectFamily::SpecularPaths,
            reference_label: "reference".into(),
            reference,
            panels: vec![panel("exact", exact), panel("schlick", schlick)],
            mask: ErrorMask::SpecularObjects,
        };
        let (written, rows) = files(&[set]).unwrap();
        assert!(rows.iter().all(|r| r.error_scale == 0.05), "{:?}", rows.iter().map(|r| r.error_scale).collect::<Vec<_>>());
        assert!(rows[1].exact.is_none(), "exact against itself");
        let against = rows[2].exact.as_ref().expect("schlick against exact");
        assert_eq!((against.scale, against.error_file.as_str()), (0.05, "effects_hero/specular_schlick_exact_error.png"));
        // Figures against exact: mean |Δ| = (49 × 0.03 + 0.9) / 300 pixel-channels.
        assert!((against.error.mean_absolute - (49.0 * 0.03 + 0.9) / 300.0).abs() < 1e-12, "{:?}", against.error);
        assert!((against.error.max_absolute - 0.9).abs() < 1e-12);
        let decoded = |name: &str| {
            let file = written.iter().find(|f| f.name == name).unwrap_or_else(|| panic!("{name}"));
            let image = nklut_tables::image_files::decode(nklut_tables::texel::Encoding::Unorm8, &file.bytes).unwrap();
            let nklut_tables::texel::Texels::U8(bytes) = image.texels else { panic!("8-bit") };
            bytes
        };
        let total = decoded("effects_hero/specular_schlick_error.png");
        // 0.04 of 0.05: 0.8 × 4 stops = 3.2, a fifth of the way from yellow (1, 0.9, 0.1) to
        // white: (1, 0.92, 0.28) → 255, 235, 71.
        assert_eq!(&total[..3], &[255, 235, 71]);
        assert_eq!(&total[99 * 3..], &[255, 255, 255]);
        // 0.01 of 0.05: 0.8 of the way from black to blue (0.1, 0.1, 0.8) → 20, 20, 163.
        assert_eq!(&total[50 * 3..51 * 3], &[20, 20, 163]);
        let own = decoded("effects_hero/specular_schlick_exact_error.png");
        // 0.03 of 0.05: 2.4 stops, 0.4 from red (0.9, 0.1, 0.1) to yellow (1, 0.9, 0.1).
        assert_eq!(&own[..3], &[240, 107, 26]);
        assert_eq!(&own[60 * 3..61 * 3], &[0, 0, 0]);
        for name in ["effects_hero/specular_error_scale.png", "effects_hero/specular_exact_error_scale.png"] {
            assert!(written.iter().any(|f| f.name == name), "{name}");
        }
        let table = hero_table(&rows);
        assert_eq!(table.rows(), 3);
    }
}
