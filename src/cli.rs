//! The binary's command-line arguments: the flags every subcommand shares and those of
//! `bake` and `validate`, each turned into the plain values the library's stages take
//! (the library itself knows nothing of flags).

use std::path::PathBuf;

use clap::builder::{PossibleValue, PossibleValuesParser, TypedValueParser};
use clap::Args;

use nklut::bake::{BakeRequest, Encoding, Layout, Source};
use nklut::fresnel::Method;
use nklut::ingest::{Config, Selection};
use nklut::recommend::{Bound, RecommendRequest};
use nklut::spectrum::{ChannelIndex, Channels, Coverage, Index};
use nklut::validate::quadrature::BRUTE_FORCE_SAMPLES;
use nklut::validate::{Strategy, ValidateRequest};

/// `--db DIR` and `--out DIR`, the same for every subcommand.
#[derive(Args, Clone, Debug)]
pub struct Paths {
    /// The refractiveindex.info database (the `database` folder or the repository above
    /// it). Default: $NKLUT_DB, else refractiveindex/database.
    #[arg(long, value_name = "DIR", global = true)]
    pub db: Option<PathBuf>,
    /// Where outputs go.
    #[arg(long, value_name = "DIR", default_value = "output", global = true)]
    pub out: PathBuf,
}

/// Which pages: `--page ID`, `--shelf NAME` (both repeatable) or `--all`.
#[derive(Args, Clone, Debug, Default)]
pub struct PageSelection {
    /// A page id such as main/Au/Johnson or 3d/metals/gold (repeatable).
    #[arg(long = "page", value_name = "ID")]
    pub pages: Vec<String>,
    /// A catalog shelf such as 3d or main (repeatable).
    #[arg(long = "shelf", value_name = "NAME")]
    pub shelves: Vec<String>,
    /// Every page of the catalog (the default when no --page or --shelf is given).
    #[arg(long)]
    pub all: bool,
}

impl PageSelection {
    pub fn selection(&self) -> Selection {
        if self.all || (self.shelves.is_empty() && self.pages.is_empty()) {
            return Selection::All;
        }
        Selection::Named { shelves: self.shelves.clone(), pages: self.pages.clone() }
    }
}

/// How every command that reads pages reads them: `--channels R,G,B`, `--visible`,
/// `--strict`.
#[derive(Args, Clone, Debug, Default)]
pub struct ChannelArgs {
    /// Channel wavelengths red,green,blue in nm (each in 360-830 nm).
    #[arg(long, value_name = "R,G,B", default_value = "685,535,475", value_parser = parse_channels)]
    pub channels: Channels,
    /// Which wavelengths a kept page's data must cover: `channels` (the three channel
    /// wavelengths; the spectral colour holds the nearest measured value outside the data)
    /// or `full` (390-700 nm).
    #[arg(long, value_name = "RULE", default_value = "channels", value_parser = parse_coverage)]
    pub visible: Coverage,
    /// Any data error other than missing coverage, and any data warning, is fatal.
    #[arg(long)]
    pub strict: bool,
}

impl ChannelArgs {
    pub fn config(&self) -> Config {
        Config { channels: self.channels, coverage: self.visible, strict: self.strict }
    }
}

fn parse_channels(text: &str) -> Result<Channels, String> {
    let values: Vec<f64> = text.split(',').map(|v| v.trim().parse::<f64>().map_err(|e| format!("{v:?}: {e}"))).collect::<Result<_, _>>()?;
    match values.as_slice() {
        &[red_nm, green_nm, blue_nm] => Channels::new(red_nm, green_nm, blue_nm),
        _ => Err("expected three wavelengths in nm, e.g. 685,535,475".into()),
    }
}

fn parse_coverage(text: &str) -> Result<Coverage, String> {
    match text {
        "channels" => Ok(Coverage::Channels),
        "full" => Ok(Coverage::Full),
        _ => Err(format!("{text:?}: expected channels or full")),
    }
}

/// A value parser over a closed set of named values, listing each with its help line.
fn named<T: Copy + Send + Sync + 'static>(
    all: &'static [T],
    name: fn(T) -> &'static str,
    help: fn(T) -> &'static str,
) -> impl TypedValueParser<Value = T> {
    PossibleValuesParser::new(all.iter().map(move |&v| PossibleValue::new(name(v)).help(help(v))))
        .map(move |text| *all.iter().find(|&&v| name(v) == text).expect("clap accepted only listed names"))
}

/// Arguments of `nklut bake`.
#[derive(Args, Clone, Debug)]
pub struct BakeArgs {
    #[command(flatten)]
    pub pages: PageSelection,
    #[command(flatten)]
    pub channels: ChannelArgs,
    /// Texels per row N (1..=65536); texel i holds F at cosθ = (i + 0.5)/N.
    #[arg(long, default_value_t = 256)]
    pub size: usize,
    /// Texel encoding (repeatable; default: all).
    #[arg(long = "encoding", value_name = "E", value_parser = named(&Encoding::ALL, Encoding::name, Encoding::description))]
    pub encodings: Vec<Encoding>,
    /// Where F comes from (repeatable; default: three-channel).
    #[arg(long = "source", value_name = "S", value_parser = named(&Source::ALL, Source::name, Source::description))]
    pub sources: Vec<Source>,
    /// File layout (repeatable; default: both).
    #[arg(long = "layout", value_name = "L", value_parser = named(&Layout::ALL, Layout::name, Layout::description))]
    pub layouts: Vec<Layout>,
}

impl BakeArgs {
    pub fn request(&self) -> BakeRequest {
        BakeRequest {
            selection: self.pages.selection(),
            reading: self.channels.config(),
            size: self.size,
            sources: self.sources.clone(),
            encodings: self.encodings.clone(),
            layouts: self.layouts.clone(),
        }
    }
}

/// Arguments of `nklut validate`.
#[derive(Args, Clone, Debug)]
pub struct ValidateArgs {
    #[command(flatten)]
    pub pages: PageSelection,
    #[command(flatten)]
    pub channels: ChannelArgs,
    /// Explicit channel indices instead of pages: "n,k;n,k;n,k" (red;green;blue), each in
    /// the methods' domain n in [1e-3, 1e3], k in [0, 1e3].
    #[arg(long, value_name = "R;G;B", value_parser = parse_nk, allow_hyphen_values = true, conflicts_with_all = ["pages", "shelves", "all"])]
    pub nk: Option<ChannelIndex>,
    /// A method to measure (repeatable; default: all). lut sweeps N x encodings.
    #[arg(long = "method", value_name = "NAME", value_parser = parse_method)]
    pub methods: Vec<Method>,
    /// Use the 10^6-sample brute force instead of adaptive quadrature.
    #[arg(long)]
    pub brute: bool,
}

impl ValidateArgs {
    pub fn request(&self) -> ValidateRequest {
        ValidateRequest {
            selection: self.pages.selection(),
            reading: self.channels.config(),
            nk: self.nk,
            methods: self.methods.clone(),
            strategy: if self.brute { Strategy::Brute(BRUTE_FORCE_SAMPLES) } else { Strategy::Fast },
        }
    }
}

/// Parse `--nk "n,k;n,k;n,k"` (red;green;blue).
fn parse_nk(text: &str) -> Result<ChannelIndex, String> {
    let channels: Vec<Index> = text
        .split(';')
        .map(|pair| {
            let values: Vec<f64> =
                pair.split(',').map(|v| v.trim().parse::<f64>().map_err(|e| format!("{v:?}: {e}"))).collect::<Result<_, _>>()?;
            match values.as_slice() {
                &[n, k] if n.is_finite() && k.is_finite() && n > 0.0 && k >= 0.0 => Ok(Index::new(n, k)),
                _ => Err(format!("{pair:?}: expected n,k with n > 0 and k >= 0")),
            }
        })
        .collect::<Result<_, _>>()?;
    channels.try_into().map_err(|_| "expected three n,k pairs red;green;blue, e.g. 0.23,3.94;0.57,2.18;1.39,1.72".to_string())
}

fn parse_method(text: &str) -> Result<Method, String> {
    Method::from_name(text).ok_or_else(|| format!("unknown method {text:?}; one of {}", Method::ALL.map(Method::name).join(", ")))
}

#[cfg(test)]
mod tests {
    use clap::Parser;

    use super::*;

    #[derive(Parser)]
    struct Bake {
        #[command(flatten)]
        args: BakeArgs,
    }

    #[test]
    fn bake_names_parse_and_unknown_names_are_refused() {
        for e in Encoding::ALL {
            let parsed = Bake::try_parse_from(["bake", "--encoding", e.name()]).unwrap();
            assert_eq!(parsed.args.encodings, vec![e]);
        }
        let parsed = Bake::try_parse_from(["bake", "--source", "spectral", "--source", "three-channel", "--layout", "atlas"]).unwrap();
        assert_eq!(parsed.args.sources, vec![Source::Spectral, Source::ThreeChannel]);
        assert_eq!(parsed.args.layouts, vec![Layout::Atlas]);
        assert!(Bake::try_parse_from(["bake", "--encoding", "unorm12"]).is_err());
        assert!(Bake::try_parse_from(["bake", "--source", "Spectral"]).is_err());
    }

    #[test]
    fn nk_argument_parses_and_rejects() {
        let parsed = parse_nk("0.23,3.94;0.57,2.18;1.39,1.72").unwrap();
        assert_eq!(parsed[1], Index::new(0.57, 2.18));
        assert!(parse_nk("0.23,3.94;0.57,2.18").is_err());
        assert!(parse_nk("0.23,3.94;0.57,x;1,1").is_err());
        assert!(parse_nk("-1,0;1,0;1,0").is_err());
    }
}

/// Arguments of `nklut recommend`.
#[derive(Args, Clone, Debug)]
pub struct RecommendArgs {
    #[command(flatten)]
    pub pages: PageSelection,
    #[command(flatten)]
    pub channels: ChannelArgs,
    /// A folder of device results (default: <out>/devices, where `make report` copies
    /// benchmarks/devices); each device with timings gets a recommendation beside the CPU's.
    #[arg(long, value_name = "DIR")]
    pub devices: Option<PathBuf>,
    /// The bound on the largest CIEDE2000 over the angle against the spectral reference curve.
    #[arg(long = "bound-de", value_name = "DE", default_value_t = Bound::default().de2000)]
    pub bound_de: f64,
    /// A second bound: the worst channel's mean relative error over the angle (a fraction;
    /// default: none).
    #[arg(long = "bound-rel", value_name = "R")]
    pub bound_rel: Option<f64>,
}

impl RecommendArgs {
    pub fn request(&self) -> RecommendRequest {
        RecommendRequest {
            selection: self.pages.selection(),
            reading: self.channels.config(),
            devices: self.devices.clone(),
            bound: Bound { de2000: self.bound_de, rel: self.bound_rel },
        }
    }
}
