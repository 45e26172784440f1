// Every shape in one record; twin of PrimitiveRecord in src/layout.rs and of src/cpu/primitive.rs.
// Sphere: centre a, radius. Quad: corner a, edges b, c. Triangle: vertex a, edges b, c.

const PRIM_SPHERE: u32 = 0u;
const PRIM_QUAD: u32 = 1u;
const PRIM_TRIANGLE: u32 = 2u;

struct Primitive {
    a: vec3<f32>,
    kind: u32,
    b: vec3<f32>,
    radius: f32,
    c: vec3<f32>,
    material: u32,
}

#include "shared/kinds.wgsl"

// Bit k is set when the scene has primitives of kind k (PackedScene::primitive_kinds), set per
// pipeline so that a scene of one shape compiles that shape's test alone: the branch on the kind
// inside the BVH loop made the book's sphere scenes about 1.4x slower on llvmpipe. 7: any kind
// (`--specialize none`).
override PRIM_KINDS: u32 = 7u;

// Whether a primitive of kind `kind` is a `k`, in a scene with the kinds PRIM_KINDS.
fn prim_is(kind: u32, k: u32) -> bool {
    return kind_is(PRIM_KINDS, kind, k);
}

#include "shared/sphere.wgsl"
#include "shared/planar.wgsl"

// Distance to the nearest hit on primitive `slot` in (t_min, t_max), or -1 for none. Reads only
// the fields the shape needs (a sphere, 20 of the record's 48 bytes) where the primitives take
// one binding; split over several (shared/scene_split.wgsl), it loads the record.
fn hit_primitive(slot: u32, ray: Ray, t_min: f32, t_max: f32) -> f32 {
    if PRIM_BINDINGS != 1u {
        let p = primitive(slot);
        if prim_is(p.kind, PRIM_SPHERE) {
            return hit_sphere_by(p.a, p.radius, ray, t_min, t_max);
        }
        return hit_planar(p.kind, p.a, p.b, p.c, ray, t_min, t_max);
    }
    if PRIM_KINDS == (1u << PRIM_SPHERE) {
        return hit_sphere_by(primitives[slot].a, primitives[slot].radius, ray, t_min, t_max);
    }
    let kind = primitives[slot].kind;
    if prim_is(kind, PRIM_SPHERE) {
        return hit_sphere_by(primitives[slot].a, primitives[slot].radius, ray, t_min, t_max);
    }
    return hit_planar(kind, primitives[slot].a, primitives[slot].b, primitives[slot].c, ray, t_min, t_max);
}

// Unit normal at `point`: outward for a sphere, b × c for a quad or triangle.
fn outward_normal(p: Primitive, point: vec3<f32>) -> vec3<f32> {
    if prim_is(p.kind, PRIM_SPHERE) {
        return sphere_normal(p, point);
    }
    return planar_normal(p);
}

fn primitive_area(p: Primitive) -> f32 {
    if prim_is(p.kind, PRIM_SPHERE) {
        return 4.0 * PI * p.radius * p.radius;
    }
    let area = length(cross(p.b, p.c));
    if prim_is(p.kind, PRIM_QUAD) {
        return area;
    }
    return 0.5 * area;
}

// A point distributed uniformly by area (Shirley's warp for triangles).
fn sample_point(p: Primitive, u1: f32, u2: f32) -> vec3<f32> {
    if prim_is(p.kind, PRIM_SPHERE) {
        return p.a + unit_vector(u1, u2) * p.radius;
    }
    if prim_is(p.kind, PRIM_QUAD) {
        return p.a + p.b * u1 + p.c * u2;
    }
    let s = sqrt(u1);
    return p.a + p.b * (s * (1.0 - u2)) + p.c * (s * u2);
}
