//! What can be wrong with a scene, as types: the file could not be read, its YAML does not
//! parse, a field's value is out of its range or names something unknown, two fields
//! contradict each other, or a mesh or the placed geometry cannot be traced. Each problem
//! carries the values it is about; its text (`Display`) names the field by its path in the
//! file (`objects[2].scale`, `effects.distance_maps.size`, `lights[1].colour`), the value
//! and what the value must be, so the message a user reads and the variant a caller or a
//! test matches on say the same thing.

use std::fmt;
use std::path::PathBuf;

use nklut_optics::db::block_yaml::TooDeep;
use nklut_optics::db::file::FileProblem;
use nklut_tables::budget::TooLarge;

use super::effects::EffectFamily;
use super::mesh::{GeometryError, MeshError};

/// A scene file that could not be used: the file, whether the values were the file's own
/// or had command-line overrides applied, and what was wrong.
#[derive(Debug, thiserror::Error)]
#[error("scene {}: {problem}{values}", file.display())]
pub struct SceneError {
    pub file: PathBuf,
    pub values: Values,
    /// Boxed: a problem carries its values, and an error is moved through every `?`.
    pub problem: Box<SceneProblem>,
}

impl SceneError {
    /// A problem with the values as the file gives them.
    pub fn new(file: impl Into<PathBuf>, problem: SceneProblem) -> Self {
        Self { file: file.into(), values: Values::AsWritten, problem: Box::new(problem) }
    }
}

/// Where the values a problem is about came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Values {
    /// The scene file as written.
    AsWritten,
    /// The scene file with the command line's overrides (`--resolution`, `--frames`, …).
    AfterOverrides,
}

impl fmt::Display for Values {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Values::AsWritten => Ok(()),
            Values::AfterOverrides => f.write_str(" (after command-line overrides)"),
        }
    }
}

/// What was wrong with a scene.
#[derive(Debug, thiserror::Error)]
pub enum SceneProblem {
    /// The file could not be read (missing, not a regular file, too large).
    #[error("cannot read: {0}")]
    Unreadable(FileProblem),
    /// The YAML nests deeper than any scene does; refused before the parser sees it.
    #[error("{0}")]
    TooDeep(TooDeep),
    /// The YAML does not parse into a scene (bad syntax, an unknown field or variant, a
    /// value of the wrong type); serde_norway's error keeps the line and column.
    #[error("{0}")]
    Syntax(serde_norway::Error),
    /// One field's value, at its path in the file.
    #[error("{}", FieldText { field, kind })]
    Field { field: String, kind: FieldProblem },
    /// Fields that contradict each other; `at` is the path of what holds them
    /// (`objects[1]`), empty at the top of the file.
    #[error("{}{conflict}", Prefix(at))]
    Conflict { at: String, conflict: Conflict },
    /// An object's mesh could not be loaded.
    #[error("objects[{object}]: {error}")]
    Mesh { object: usize, error: MeshError },
    /// The placed meshes cannot be traced.
    #[error("{0}")]
    Geometry(GeometryError),
    /// A specular object's material has no optical constants.
    #[error("objects[{object}].material {page} has no optical constants")]
    NoOpticalConstants { object: usize, page: String },
    /// What the scene asks for would not fit the memory budget.
    #[error("{0}")]
    Memory(TooLarge),
}

impl SceneProblem {
    /// A problem with `field`.
    pub fn field(field: impl Into<String>, kind: FieldProblem) -> Self {
        SceneProblem::Field { field: field.into(), kind }
    }

    /// The problem of a part of the scene seen from what holds it: its field paths
    /// prefixed with `parent` (`scale` in `objects[2]` is `objects[2].scale`; a problem of
    /// the part as a whole, with an empty path, is `parent`'s).
    pub fn within(self, parent: &str) -> Self {
        match self {
            SceneProblem::Field { field, kind } => {
                SceneProblem::Field { field: if field.is_empty() { parent.to_string() } else { format!("{parent}.{field}") }, kind }
            }
            SceneProblem::Conflict { at, conflict } => {
                SceneProblem::Conflict { at: if at.is_empty() { parent.to_string() } else { format!("{parent}.{at}") }, conflict }
            }
            other => other,
        }
    }
}

/// `objects[1].` before a conflict's fields, nothing at the top of the file.
struct Prefix<'a>(&'a str);

impl fmt::Display for Prefix<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.0.is_empty() {
            Ok(())
        } else {
            write!(f, "{}.", self.0)
        }
    }
}

/// What is wrong with one field's value.
#[derive(Clone, Debug, PartialEq)]
pub enum FieldProblem {
    /// The value lies outside the field's range.
    OutOfRange { value: Value, range: Range },
    /// The value must be finite.
    NotFinite,
    /// A direction or axis of length zero (or with a non-finite component).
    ZeroVector { value: [f64; 3] },
    /// A name that is not one of the known ones (`what`: a method, …).
    Unknown { what: &'static str, name: String, known: Vec<&'static str> },
    /// A list, or the scene, holds none of what it needs.
    Empty(Listing),
    /// A field the object needs is not there.
    Missing(Required),
    /// A material that is not a page id `shelf/book/page`.
    NotAPageId { value: String },
    /// A field only a scene with an `effects` section may use.
    NeedsEffects,
    /// A field only the effects of one family use.
    NeedsFamily(EffectFamily),
}

/// The text of a field's problem: the path, then the value and what it must be, or what
/// is wrong.
struct FieldText<'a> {
    field: &'a str,
    kind: &'a FieldProblem,
}

impl fmt::Display for FieldText<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let field = self.field;
        match self.kind {
            FieldProblem::OutOfRange { value, range } => write!(f, "{field} {value} must {range}"),
            FieldProblem::NotFinite => write!(f, "{field} must be finite"),
            FieldProblem::ZeroVector { value } => write!(f, "{field} {value:?} must be a non-zero vector"),
            FieldProblem::Unknown { what, name, known } => write!(f, "{field}: unknown {what} {name:?}; known: {}", known.join(", ")),
            FieldProblem::Empty(listing) => write!(f, "{field}: {listing}"),
            FieldProblem::Missing(required) => write!(f, "{field}: {required}"),
            FieldProblem::NotAPageId { value } => write!(f, "{field} {value:?} is not a page id shelf/book/page"),
            FieldProblem::NeedsEffects => write!(f, "{field}: only a scene with an `effects` section may use it"),
            FieldProblem::NeedsFamily(family) => write!(f, "{field}: only {} ({}) use it", family.description(), family.keys().join(", ")),
        }
    }
}

/// A value as a message shows it.
#[derive(Clone, Debug, PartialEq)]
pub enum Value {
    Integer(u64),
    Number(f64),
    /// A point, a scale, a colour.
    Vector([f64; 3]),
    /// A list of counts (depths, search steps).
    Integers(Vec<u32>),
    /// A width and a height.
    Size([u32; 2]),
}

impl fmt::Display for Value {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Value::Integer(x) => write!(f, "{x}"),
            Value::Number(x) => write!(f, "{}", Shown(*x, false)),
            Value::Vector(v) => write!(f, "[{}, {}, {}]", Shown(v[0], true), Shown(v[1], true), Shown(v[2], true)),
            Value::Integers(list) => write!(f, "{list:?}"),
            Value::Size([w, h]) => write!(f, "{w}x{h}"),
        }
    }
}

/// A number as a message shows a value: plainly within 1e-6..1e16 (and 0; as `{:?}` writes
/// it when the flag says so, `1.0` for a vector's component), in exponent form beyond
/// (1e308 as `1e308`, not 309 digits).
struct Shown(f64, bool);

impl fmt::Display for Shown {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let Shown(x, debug) = *self;
        if !(x == 0.0 || !x.is_finite() || (1e-6..1e16).contains(&x.abs())) {
            write!(f, "{x:e}")
        } else if debug {
            write!(f, "{x:?}")
        } else {
            write!(f, "{x}")
        }
    }
}

/// The values a field may take.
#[derive(Clone, Debug, PartialEq)]
pub enum Range {
    /// Whole numbers `low..=high` (each of a list).
    Integers { low: u64, high: u64 },
    /// `[low, high]` for each component of a vector, or for a number.
    Closed { low: f64, high: f64, each: Each },
    /// `(low, high)`.
    Open { low: f64, high: f64 },
    /// `(low, high]`.
    AboveUpTo { low: f64, high: f64 },
    /// Every component within ±`bound`.
    Within { bound: f64 },
    /// Above `low`, for the reason given.
    Above { low: f64, why: &'static str },
    /// Above zero.
    Positive,
    /// Between 1×1 and `largest`.
    Sizes { largest: [u32; 2] },
    /// Layers of the distance maps: at least one specular layer and the diffuse one.
    Layers { low: u64, high: u64 },
}

/// What a closed range applies to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Each {
    /// The value (a number).
    Whole,
    /// Each axis of a vector.
    Axis,
    /// Each colour channel.
    Channel,
}

/// A bound as a message writes it: small whole numbers plainly (`0`, `1`, `180`), the rest
/// in exponent form (`1e-4`, `1e6`).
struct Bound(f64);

impl fmt::Display for Bound {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.0.fract() == 0.0 && self.0.abs() < 1000.0 {
            write!(f, "{}", self.0)
        } else {
            write!(f, "{:e}", self.0)
        }
    }
}

impl fmt::Display for Range {
    /// The predicate after "must": `lie in 1..=8`, `be positive`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Range::Integers { low, high } => write!(f, "lie in {low}..={high}"),
            Range::Closed { low, high, each } => {
                let each = match each {
                    Each::Whole => "",
                    Each::Axis => " on each axis",
                    Each::Channel => " per channel",
                };
                write!(f, "lie in [{}, {}]{each}", Bound(low), Bound(high))
            }
            Range::Open { low, high } => write!(f, "lie in ({}, {})", Bound(low), Bound(high)),
            Range::AboveUpTo { low, high } => write!(f, "lie in ({}, {}]", Bound(low), Bound(high)),
            Range::Within { bound } => write!(f, "lie within ±{} on each axis", Bound(bound)),
            Range::Above { low, why } => write!(f, "be above {} ({why})", Bound(low)),
            Range::Positive => f.write_str("be positive"),
            Range::Sizes { largest: [w, h] } => write!(f, "be between 1x1 and {w}x{h}"),
            Range::Layers { low, high } => write!(f, "lie in {low}..={high} (at least one specular layer and the diffuse one)"),
        }
    }
}

/// What a list, or the scene, must hold at least one of.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Listing {
    Objects,
    SpecularObjects,
    Measurements,
    Effects,
    Methods,
    /// A list of numbers with none in it.
    Values,
}

impl fmt::Display for Listing {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Listing::Objects => f.write_str("the scene names no object"),
            Listing::SpecularObjects => f.write_str("the scene names no specular object (one with a material)"),
            Listing::Measurements => f.write_str("name at least one of timing, image_error"),
            Listing::Effects => {
                let keys: Vec<&str> = EffectFamily::ALL.iter().flat_map(|family| family.keys().iter().copied()).collect();
                write!(f, "name at least one effect: {}", keys.join(", "))
            }
            Listing::Methods => f.write_str("no method named"),
            Listing::Values => f.write_str("the list holds no value"),
        }
    }
}

/// A field an object needs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Required {
    /// A specular object's Fresnel methods.
    Methods,
    /// What the object is: a material (specular) or a diffuse colour.
    MaterialOrDiffuse,
}

impl fmt::Display for Required {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Required::Methods => f.write_str("a specular object needs at least one method"),
            Required::MaterialOrDiffuse => f.write_str("name a page id (a specular object) or a `diffuse` colour"),
        }
    }
}

/// Fields that contradict each other; the text names them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Conflict {
    /// An object with a material and a diffuse colour.
    MaterialAndDiffuse,
    /// A pattern on a specular object.
    PatternOnSpecular,
    /// Fresnel methods on a diffuse object.
    MethodsOnDiffuse,
    /// Both `light` and `lights`.
    LightAndLights,
}

impl fmt::Display for Conflict {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Conflict::MaterialAndDiffuse => "material and diffuse: an object is either specular (a material) or diffuse, not both",
            Conflict::PatternOnSpecular => "pattern: only a diffuse object has a pattern",
            Conflict::MethodsOnDiffuse => "methods: a diffuse object has no Fresnel method",
            Conflict::LightAndLights => "light and lights: name the lights once, in `lights` (directional, point, ambient) or in `light`",
        })
    }
}
