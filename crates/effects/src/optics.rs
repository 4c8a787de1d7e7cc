//! What happens where a path meets a specular surface: the Fresnel weight of each channel
//! from any method of the `fresnel` module, the mirror direction, Snell's refraction and
//! total internal reflection — the bounce rule of Umenhoffer, Patow and Szirmay-Kalos (GPU
//! Gems 3 ch. 17, "Robust Multiple Specular Reflections and Refractions"), with F from the
//! scene's method instead of only Schlick's.
//!
//! A conductor reflects with weight F. A dielectric reflects with weight F and refracts
//! with weight 1 − F; a ray arriving from inside (V·N > 0) flips the normal and sees the
//! relative index 1/η, whose exact curve has a total-internal-reflection region (F = 1 past
//! the critical angle). Where no refracted direction exists the refracted share turns back
//! as a mirror reflection with weight 1. Directions follow one index per material, the
//! geometric channel's n (green, no dispersion); weights are per channel.

use glam::DVec3;

use nklut_optics::fresnel::{LutSpec, Method, Model};
use nklut_optics::spectrum::{ChannelIndex, Index, Kind};

/// The channel whose n bends refracted rays (green: the middle of the visible range).
pub const GEOMETRIC_CHANNEL: usize = 1;

/// How F is read for a ray that meets a dielectric's surface from inside.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum InsideReflectance {
    /// The method's curve of the inside index conj(1/η) at the angle of incidence, per
    /// channel: the GPU algorithm's rule (its `lut` bakes that curve). With one refracted
    /// direction for all channels (the geometric channel's), a channel whose own critical
    /// angle is smaller than the geometric channel's meets F = 1 where the geometric
    /// channel leaves: past asin(n_g/n_b) from outside, blue never leaves a sphere.
    InsideCurve,
    /// The interface the path actually crosses: where the geometric channel refracts out at
    /// θₜ, each channel's F is its outside curve at θₜ (Stokes reciprocity, F(θᵢ, 1/η) =
    /// F(θₜ, η) for one pair of angles, exact for k = 0), so every channel conserves energy
    /// at every bounce (F + (1 − F) = 1) on the geometry the path takes; where the geometric
    /// channel is totally reflected, every channel is (weight 1). What a three-channel
    /// renderer with one geometry can do: the channels' own critical angles are lost, their
    /// energy is not. The f64 reference's rule.
    TransmittedAngle,
}

/// The Fresnel curves of one specular material for one method: seen from outside (index
/// η = n + ik) and from inside (1/η, conjugated so k stays ≥ 0: the reflectance is the same),
/// the rule for rays from inside, and the Beer–Lambert attenuation inside it.
#[derive(Clone, Debug)]
pub struct SpecularOptics {
    pub kind: Kind,
    /// n of [`GEOMETRIC_CHANNEL`], for Snell's law.
    pub geometric_n: f64,
    pub outside: [Model; 3],
    pub inside: [Model; 3],
    pub inside_rule: InsideReflectance,
    /// Attenuation coefficient per channel inside a dielectric, per scene unit of path:
    /// α = 4πk/λ (Beer–Lambert) times the scene's metres per unit; zero: no attenuation
    /// (the GPU algorithm's distance maps carry none).
    pub absorption: [f64; 3],
}

/// The index seen from inside a medium of index η = n + ik: conj(1/η) = (n + ik)/(n² + k²).
pub fn inside_index(index: Index) -> Index {
    let norm = index.n * index.n + index.k * index.k;
    if norm > 0.0 {
        Index::new(index.n / norm, index.k / norm)
    } else {
        Index::new(1.0, 0.0)
    }
}

/// The Beer–Lambert attenuation coefficient per scene unit of an extinction coefficient k
/// at `wavelength_nm`: α = 4πk/λ (the intensity falls as e^(−αd)), λ in metres, times
/// `metres_per_unit`. Zero for k ≤ 0 or a non-finite input.
pub fn attenuation_per_unit(k: f64, wavelength_nm: f64, metres_per_unit: f64) -> f64 {
    let alpha = 4.0 * std::f64::consts::PI * k / (wavelength_nm * 1e-9) * metres_per_unit;
    if alpha.is_finite() && alpha > 0.0 {
        alpha
    } else {
        0.0
    }
}

impl SpecularOptics {
    /// `lut` sizes the texture of the `lut` method (one curve from outside, one from inside).
    /// The GPU algorithm's rules: [`InsideReflectance::InsideCurve`], no attenuation.
    pub fn new(channels: &ChannelIndex, kind: Kind, method: Method, lut: LutSpec) -> Self {
        Self {
            kind,
            geometric_n: channels[GEOMETRIC_CHANNEL].n,
            outside: channels.map(|index| Model::new(index, method, lut)),
            inside: channels.map(|index| Model::new(inside_index(index), method, lut)),
            inside_rule: InsideReflectance::InsideCurve,
            absorption: [0.0; 3],
        }
    }

    /// The f64 reference's optics: exact Fresnel, [`InsideReflectance::TransmittedAngle`],
    /// and inside a dielectric the attenuation of each channel's k at its wavelength
    /// (`wavelengths_nm`, red, green, blue) over paths in units of `metres_per_unit`.
    pub fn reference(channels: &ChannelIndex, kind: Kind, wavelengths_nm: [f64; 3], metres_per_unit: f64) -> Self {
        let mut optics = Self::new(channels, kind, Method::Exact, LutSpec::default());
        optics.inside_rule = InsideReflectance::TransmittedAngle;
        if kind == Kind::Dielectric {
            optics.absorption = std::array::from_fn(|c| attenuation_per_unit(channels[c].k, wavelengths_nm[c], metres_per_unit));
        }
        optics
    }

    fn reflectance(&self, from_inside: bool, cos_theta: f64) -> [f64; 3] {
        let models = if from_inside { &self.inside } else { &self.outside };
        std::array::from_fn(|c| models[c].reflectance(cos_theta))
    }

    /// e^(−α d) per channel over a path of `distance` scene units inside the material.
    pub fn transmittance(&self, distance: f64) -> [f64; 3] {
        self.absorption.map(|alpha| if alpha > 0.0 { (-alpha * distance).exp() } else { 1.0 })
    }
}

/// Which bounces a path may still take at this surface.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Allowed {
    pub reflection: bool,
    pub refraction: bool,
}

/// How a branch left the surface.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Turn {
    Reflection,
    Refraction,
    /// The refracted share turned back: no refracted direction exists.
    TotalInternalReflection,
}

/// One way a path continues from a surface: a unit direction, a weight per channel, and
/// whether it runs on inside the material (where it is attenuated).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Branch {
    pub direction: DVec3,
    pub weight: [f64; 3],
    pub turn: Turn,
    pub inside: bool,
}

/// Mirror direction of unit `incoming` about unit `normal`: V − 2(V·N)N.
pub fn reflect(incoming: DVec3, normal: DVec3) -> DVec3 {
    incoming - normal * (2.0 * incoming.dot(normal))
}

/// Snell's law for unit `incoming` against unit `normal` (facing the incoming ray, V·N ≤ 0)
/// with relative index `eta` = n_from/n_to: ηV + (η cosθᵢ − cosθₜ)N, cos²θₜ = 1 − η²(1 −
/// cos²θᵢ); `None` past the critical angle.
pub fn refract(incoming: DVec3, normal: DVec3, eta: f64) -> Option<DVec3> {
    let cos_i = -incoming.dot(normal);
    let cos_t2 = 1.0 - eta * eta * (1.0 - cos_i * cos_i);
    (cos_t2 >= 0.0).then(|| (incoming * eta + normal * (eta * cos_i - cos_t2.sqrt())).normalize())
}

/// The side a ray meets a surface from and the normal its bounce uses: the surface's own
/// plane (`geometric`, the triangle's normal on the mesh's outside) decides the side, so a
/// grazing ray on a coarse mesh whose interpolated `normal` faces the other way is still
/// seen arriving from where it came; the bounce takes the interpolated normal turned to
/// that side, or the plane's own where the interpolated one faces away from the ray.
/// Returns (from inside, the unit normal facing the ray, cosθᵢ ∈ [0, 1]). The GPU's twin
/// (`facing` in shaders/specular.wgsl) takes the side at the camera's hit from the
/// rasteriser's `front_facing` on meshes wound outwards by the same plane rule
/// (`scene::mesh::wound_against_normals`), and the plane from the screen derivatives of
/// the hit point.
pub fn facing(incoming: DVec3, normal: DVec3, geometric: DVec3) -> (bool, DVec3, f64) {
    let from_inside = incoming.dot(geometric) > 0.0;
    let side = if from_inside { -1.0 } else { 1.0 };
    let smooth = normal * side;
    let cos_smooth = -incoming.dot(smooth);
    if cos_smooth > 0.0 {
        (from_inside, smooth, cos_smooth.min(1.0))
    } else {
        let plane = geometric * side;
        (from_inside, plane, (-incoming.dot(plane)).clamp(0.0, 1.0))
    }
}

/// The branches leaving a specular surface hit by unit `incoming` with unit shading
/// `normal` (the mesh's outward normal) on a surface whose own plane has the outward unit
/// normal `geometric` ([`facing`]): at most two.
pub fn scatter(optics: &SpecularOptics, incoming: DVec3, normal: DVec3, geometric: DVec3, allowed: Allowed) -> Vec<Branch> {
    let (from_inside, facing, cos_i) = facing(incoming, normal, geometric);
    let mirror = reflect(incoming, facing);
    let mut branches = Vec::with_capacity(2);
    if optics.kind == Kind::Conductor {
        if allowed.reflection {
            branches.push(Branch { direction: mirror, weight: optics.reflectance(false, cos_i), turn: Turn::Reflection, inside: false });
        }
        return branches;
    }
    let eta = if from_inside { optics.geometric_n } else { 1.0 / optics.geometric_n };
    let refracted = refract(incoming, facing, eta);
    let reflectance = match (from_inside, optics.inside_rule, refracted) {
        (false, _, _) => optics.reflectance(false, cos_i),
        (true, InsideReflectance::InsideCurve, _) => optics.reflectance(true, cos_i),
        (true, InsideReflectance::TransmittedAngle, Some(out)) => optics.reflectance(false, out.dot(-facing).clamp(0.0, 1.0)),
        (true, InsideReflectance::TransmittedAngle, None) => [1.0; 3],
    };
    // The reflected branch stays on the side it came from; the refracted one crosses.
    let reflection = Branch { direction: mirror, weight: reflectance, turn: Turn::Reflection, inside: from_inside };
    match refracted {
        Some(direction) => {
            if allowed.reflection {
                branches.push(reflection);
            }
            if allowed.refraction {
                branches.push(Branch { direction, weight: reflectance.map(|f| 1.0 - f), turn: Turn::Refraction, inside: !from_inside });
            }
        }
        None if allowed.refraction => {
            branches.push(Branch { direction: mirror, weight: [1.0; 3], turn: Turn::TotalInternalReflection, inside: from_inside })
        }
        None if allowed.reflection => branches.push(reflection),
        None => {}
    }
    branches
}

#[cfg(test)]
mod tests {
    use super::*;
    use nklut_optics::fresnel::exact;

    fn glass(method: Method) -> SpecularOptics {
        let index = [Index::new(1.49, 0.0), Index::new(1.5, 0.0), Index::new(1.51, 1e-7)];
        SpecularOptics::new(&index, Kind::Dielectric, method, LutSpec::default())
    }

    const BOTH: Allowed = Allowed { reflection: true, refraction: true };

    /// A unit direction travelling down onto the plane z = 0 (normal +z) at angle θ.
    fn arriving(theta: f64) -> DVec3 {
        DVec3::new(theta.sin(), 0.0, -theta.cos())
    }

    #[test]
    fn exact_reflected_and_transmitted_weights_sum_to_one_per_bounce() {
        let optics = glass(Method::Exact);
        for degrees in [0.0, 10.0, 30.0, 56.3, 70.0, 85.0, 89.0] {
            let theta = f64::to_radians(degrees);
            // From outside, and from inside (past 41.8° the refracted share turns back).
            for (incoming, normal) in [(arriving(theta), DVec3::Z), (DVec3::new(theta.sin(), 0.0, theta.cos()), DVec3::Z)] {
                let branches = scatter(&optics, incoming, normal, normal, BOTH);
                let total: Vec<f64> = (0..3).map(|c| branches.iter().map(|b| b.weight[c]).sum()).collect();
                assert!(total.iter().all(|t| (t - 1.0).abs() < 1e-15), "{degrees}°: {total:?}");
            }
        }
        // Normal incidence from outside: F = ((n − 1)/(n + 1))² per channel.
        let branches = scatter(&optics, DVec3::NEG_Z, DVec3::Z, DVec3::Z, BOTH);
        assert!((branches[0].weight[1] - 0.04).abs() < 1e-15);
        assert!((branches[0].weight[0] - (0.49f64 / 2.49).powi(2)).abs() < 1e-15);
    }

    #[test]
    fn snell_bends_towards_the_normal_going_in_and_away_coming_out() {
        let optics = glass(Method::Exact);
        let theta = 40f64.to_radians();
        let inward = scatter(&optics, arriving(theta), DVec3::Z, DVec3::Z, BOTH);
        let refracted = inward.iter().find(|b| b.turn == Turn::Refraction).unwrap();
        // sinθₜ = sinθᵢ/1.5, travelling on into −z.
        assert!((refracted.direction.x - theta.sin() / 1.5).abs() < 1e-15 && refracted.direction.z < 0.0);
        // From inside (the ray meets the outward normal from behind) at 30°: sinθₜ = 1.5 sin 30° = 0.75.
        let inside_ray = DVec3::new(0.5, 0.0, 3f64.sqrt() / 2.0);
        let outward = scatter(&optics, inside_ray, DVec3::Z, DVec3::Z, BOTH);
        let out = outward.iter().find(|b| b.turn == Turn::Refraction).unwrap();
        assert!((out.direction.x - 0.75).abs() < 1e-15 && out.direction.z > 0.0);
        // Its F is that of the inside index 1/1.5 at 30°.
        let reflected = outward.iter().find(|b| b.turn == Turn::Reflection).unwrap();
        assert!((reflected.weight[1] - exact(1.0 / 1.5, 0.0, 30f64.to_radians().cos())).abs() < 1e-15);
        assert!((reflected.direction - DVec3::new(0.5, 0.0, -(3f64.sqrt()) / 2.0)).length() < 1e-15);
    }

    #[test]
    fn past_the_critical_angle_inside_glass_the_ray_reflects_with_weight_one() {
        // Critical angle asin(1/1.5) = 41.81°; at 45° from inside no refracted ray exists.
        let critical = (1.0f64 / 1.5).asin();
        assert!((critical.to_degrees() - 41.810_314_895_778_6).abs() < 1e-9);
        for method in [Method::Exact, Method::Schlick, Method::Lut] {
            let optics = glass(method);
            let theta = 45f64.to_radians();
            let inside_ray = DVec3::new(theta.sin(), 0.0, theta.cos());
            let branches = scatter(&optics, inside_ray, DVec3::Z, DVec3::Z, BOTH);
            assert_eq!(branches.len(), 1, "{method}");
            assert_eq!(branches[0].turn, Turn::TotalInternalReflection);
            assert_eq!(branches[0].weight, [1.0; 3]);
            assert!((branches[0].direction - DVec3::new(theta.sin(), 0.0, -theta.cos())).length() < 1e-15);
            // Just inside the critical angle a refracted ray still exists.
            let below = critical - 1e-6;
            let grazing = scatter(&optics, DVec3::new(below.sin(), 0.0, below.cos()), DVec3::Z, DVec3::Z, BOTH);
            assert!(grazing.iter().any(|b| b.turn == Turn::Refraction));
        }
        // With reflection only, past the critical angle exact F is 1 anyway (to within the
        // blue channel's absorption, k = 1e-7).
        let only =
            scatter(&glass(Method::Exact), DVec3::new(0.8, 0.0, 0.6), DVec3::Z, DVec3::Z, Allowed { reflection: true, refraction: false });
        assert_eq!((only.len(), only[0].turn), (1, Turn::Reflection));
        assert!(only[0].weight.iter().all(|f| (f - 1.0).abs() < 1e-5), "{:?}", only[0].weight);
    }

    #[test]
    fn a_conductor_only_reflects_and_nothing_is_allowed_means_no_branch() {
        let gold = [Index::new(0.16, 3.8), Index::new(0.5, 2.2), Index::new(1.2, 1.8)];
        let optics = SpecularOptics::new(&gold, Kind::Conductor, Method::Exact, LutSpec::default());
        let branches = scatter(&optics, arriving(0.3), DVec3::Z, DVec3::Z, BOTH);
        assert_eq!(branches.len(), 1);
        assert_eq!(branches[0].weight[0], exact(0.16, 3.8, 0.3f64.cos()));
        assert!(
            scatter(&glass(Method::Exact), arriving(0.3), DVec3::Z, DVec3::Z, Allowed { reflection: false, refraction: false }).is_empty()
        );
    }
}
