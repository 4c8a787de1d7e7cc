// nklut scene meshes as the effect passes draw them (`SceneMeshes` in
// crates/gpu/src/passes/distance_maps.rs): a position and a normal per vertex; each object is one
// draw whose instance index is the object's index in the scene, passed on flat.

struct MeshVertexIn {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
}

struct MeshVertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) @interpolate(flat) object: u32,
}
