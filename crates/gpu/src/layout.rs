//! One check for every struct Rust and WGSL share. Each `#[repr(C)]` struct the runner
//! uploads to (or reads back from) a shader is registered with [`shared_struct!`], which
//! names every field (a field left out does not compile: the macro destructures the struct
//! without `..`) and takes each field's offset (`std::mem::offset_of!`) and size; the tests
//! take every module a pass compiles (`passes::interfaces`), reflect it with naga (wgpu's own WGSL front end) and
//! hold each struct reachable from a uniform or storage binding to its Rust twin: the same
//! members in the same order, at the same offsets, of the same sizes, and the same size.
//! Padding members (`pad…`) are compared as the byte ranges they fill, so `pad: [u32; 3]`
//! in Rust matches `pad0`, `pad1`, `pad2` in WGSL. A struct the shaders share without a
//! registered twin, or a twin no shader has, fails the tests too.

/// One member of a shared struct: its name, offset and size in bytes.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Member {
    pub name: String,
    pub offset: usize,
    pub size: usize,
}

/// A Rust struct the shaders read or write, with the name of its WGSL twin.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SharedStruct {
    /// The struct's name in `shaders/`.
    pub wgsl: &'static str,
    /// The Rust type, in messages.
    pub rust: &'static str,
    pub size: usize,
    /// Every field, in declaration order.
    pub members: Vec<Member>,
}

/// The size of the field that `field` projects (the type of `&value.field`).
#[doc(hidden)]
pub fn field_size<T, U>(_field: fn(&T) -> &U) -> usize {
    std::mem::size_of::<U>()
}

/// The [`SharedStruct`] of a Rust struct and its WGSL twin:
/// `shared_struct!(MaterialUniform as "MaterialParams" { n, k, … })`, every field in
/// declaration order.
macro_rules! shared_struct {
    ($ty:ident as $wgsl:literal { $($field:ident),+ $(,)? }) => {{
        // Every field is named: a field added to the struct and not here does not compile.
        #[allow(dead_code)]
        fn every_field(value: $ty) {
            let $ty { $($field: _),+ } = value;
        }
        $crate::layout::SharedStruct {
            wgsl: $wgsl,
            rust: stringify!($ty),
            size: std::mem::size_of::<$ty>(),
            members: vec![$($crate::layout::Member {
                name: stringify!($field).to_string(),
                offset: std::mem::offset_of!($ty, $field),
                size: $crate::layout::field_size(|value: &$ty| &value.$field),
            }),+],
        }
    }};
}
pub(crate) use shared_struct;

/// `members` with each run of adjacent padding members (`pad…`) merged into one `pad`
/// member covering the same bytes.
pub fn merged_padding(members: &[Member]) -> Vec<Member> {
    let mut merged: Vec<Member> = Vec::new();
    for member in members {
        let padding = member.name.starts_with("pad");
        match merged.last_mut() {
            Some(last) if padding && last.name == "pad" && last.offset + last.size == member.offset => last.size += member.size,
            _ => merged.push(Member { name: if padding { "pad".into() } else { member.name.clone() }, ..member.clone() }),
        }
    }
    merged
}

/// `MaterialUniform` against `MaterialParams`: its fields, with the methods' members
/// (`methods: [[f32; 4]; N]`) named one vec4 each as the generated WGSL names them.
fn material_params() -> SharedStruct {
    use crate::params::{uniform_members, MaterialUniform};
    let fields = shared_struct!(MaterialUniform as "MaterialParams" { n, k, f0, methods, constant_colour });
    let vec4 = std::mem::size_of::<[f32; 4]>();
    let mut members = Vec::new();
    let mut names = uniform_members().into_iter();
    for field in fields.members {
        let count = field.size / vec4;
        for i in 0..count {
            let name = names.next().unwrap_or("(a member WGSL lacks)").to_string();
            members.push(Member { name, offset: field.offset + i * vec4, size: vec4 });
        }
    }
    members.extend(names.map(|name| Member { name: format!("{name} (a member Rust lacks)"), offset: 0, size: 0 }));
    SharedStruct { members, ..fields }
}

/// Every struct Rust shares with `shaders/`.
pub fn shared_structs() -> Vec<SharedStruct> {
    use crate::distance_search::{SearchHit, SearchRay};
    use crate::passes::ao::GpuDisc;
    use crate::passes::distance_maps::{DiffuseUniform, FaceUniform, LightItem, LightsUniform, MapObjectUniform, MapView, StepsUniform};
    use crate::passes::specular::{FrameUniform, ObjectUniform};
    use crate::render::ViewUniform;
    let mut structs = vec![
        material_params(),
        shared_struct!(ViewUniform as "View" { view_proj, eye, viewport }),
        shared_struct!(MapView as "MapView" { centre, size, layers, base, pad }),
        shared_struct!(StepsUniform as "SearchSteps" { linear, secant, pad }),
        shared_struct!(DiffuseUniform as "DiffuseSurface" { albedo, second, shape, kind }),
        shared_struct!(LightItem as "LightItem" { kind, vector, colour }),
        shared_struct!(LightsUniform as "Lights" { count, items }),
        shared_struct!(FaceUniform as "MapFace" { centre, face, peel, near, far }),
        shared_struct!(MapObjectUniform as "MapObject" { surface, specular }),
        shared_struct!(FrameUniform as "EffectFrame" { view_proj, eye, lights, steps, depths }),
        shared_struct!(ObjectUniform as "SceneObject" { surface, role, geometric_n, map }),
        shared_struct!(SearchRay as "SearchRay" { origin, direction }),
        shared_struct!(SearchHit as "SearchHit" { point, at }),
        shared_struct!(GpuDisc as "Disc" { centre_area, normal }),
    ];
    structs.extend(crate::distance_search::shared_structs());
    structs.extend(crate::passes::ao::shared_structs());
    structs.extend(crate::passes::gtao::shared_structs());
    structs
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The struct types reachable from `ty` (itself, its members', array elements'),
    /// each once, into `found`.
    fn structs_in(module: &naga::Module, ty: naga::Handle<naga::Type>, found: &mut Vec<naga::Handle<naga::Type>>) {
        match &module.types[ty].inner {
            naga::TypeInner::Struct { members, .. } if !found.contains(&ty) => {
                found.push(ty);
                for member in members {
                    structs_in(module, member.ty, found);
                }
            }
            naga::TypeInner::Array { base, .. } | naga::TypeInner::BindingArray { base, .. } => structs_in(module, *base, found),
            _ => {}
        }
    }

    /// The WGSL struct `ty` as [`Member`]s (names, naga's offsets and sizes) and its size.
    fn wgsl_members(module: &naga::Module, ty: naga::Handle<naga::Type>) -> (Vec<Member>, usize) {
        let naga::TypeInner::Struct { members, span } = &module.types[ty].inner else { unreachable!("structs_in finds structs") };
        let members = members
            .iter()
            .map(|m| Member {
                name: m.name.clone().unwrap_or_default(),
                offset: m.offset as usize,
                size: module.types[m.ty].inner.size(module.to_ctx()) as usize,
            })
            .collect();
        (members, *span as usize)
    }

    /// Every struct reachable from a uniform or storage binding of every module a pass
    /// compiles (`passes::interfaces`, each variant) has a registered Rust twin with its
    /// layout, and every registered twin is in some module.
    #[test]
    fn every_struct_rust_and_wgsl_share_has_one_layout() {
        let registered = shared_structs();
        let mut seen: Vec<&str> = Vec::new();
        let mut problems = Vec::new();
        let modules: Vec<crate::passes::Variant> = crate::passes::interfaces().unwrap().into_iter().flat_map(|(_, v)| v).collect();
        for variant in &modules {
            let (name, source) = (&variant.name, &variant.wgsl);
            let module = naga::front::wgsl::parse_str(source).unwrap_or_else(|e| panic!("{name}: {}", e.emit_to_string(source)));
            let mut shared = Vec::new();
            for (_, global) in module.global_variables.iter() {
                if matches!(global.space, naga::AddressSpace::Uniform | naga::AddressSpace::Storage { .. }) {
                    structs_in(&module, global.ty, &mut shared);
                }
            }
            for ty in shared {
                let wgsl_name = module.types[ty].name.clone().unwrap_or_default();
                let Some(rust) = registered.iter().find(|s| s.wgsl == wgsl_name) else {
                    problems.push(format!("{name}: struct {wgsl_name} has no Rust twin in layout::shared_structs"));
                    continue;
                };
                seen.push(rust.wgsl);
                let (members, size) = wgsl_members(&module, ty);
                if merged_padding(&members) != merged_padding(&rust.members) {
                    problems.push(format!(
                        "{name}: {wgsl_name} {:?}\n  against {} {:?}",
                        merged_padding(&members),
                        rust.rust,
                        merged_padding(&rust.members)
                    ));
                }
                if size != rust.size {
                    problems.push(format!("{name}: {wgsl_name} is {size} bytes, {} {}", rust.rust, rust.size));
                }
            }
        }
        for rust in &registered {
            if !seen.contains(&rust.wgsl) {
                problems.push(format!("{} is registered as {}, which no shader binds", rust.rust, rust.wgsl));
            }
        }
        assert!(problems.is_empty(), "{}", problems.join("\n"));
    }

    /// The check sees what it must: a member moved, resized or renamed, and padding merged
    /// only where it is adjacent.
    #[test]
    fn padding_merges_and_a_moved_member_differs() {
        let member = |name: &str, offset, size| Member { name: name.into(), offset, size };
        let rust = [member("count", 0, 4), member("pad", 4, 12)];
        let wgsl = [member("count", 0, 4), member("pad0", 4, 4), member("pad1", 8, 4), member("pad2", 12, 4)];
        assert_eq!(merged_padding(&rust), merged_padding(&wgsl));
        let moved = [member("count", 4, 4), member("pad0", 0, 4)];
        assert_ne!(merged_padding(&rust), merged_padding(&moved));
        let renamed = [member("total", 0, 4), member("pad", 4, 12)];
        assert_ne!(merged_padding(&rust), merged_padding(&renamed));
        assert_eq!(merged_padding(&[member("a", 0, 4), member("pad", 4, 4), member("b", 8, 4), member("pad1", 12, 4)]).len(), 4);
    }
}
