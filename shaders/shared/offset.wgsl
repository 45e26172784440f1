// Where a ray leaves a surface (--ray-offset), and the failure counters; twin of
// src/cpu/offset.rs. With `tmin` the hit point is o + t·d and the next ray starts there, hits
// nearer than frame.t_min ignored (the book). With `robust` (pbrt-v4's OffsetRayOrigin) the
// point is recomputed from the surface with a bound on its rounding error, and the next ray
// starts off the surface by that bound, rounded away from it; hits need only t > 0.

// Pipeline constant: `--ray-offset robust`.
override RAY_ROBUST: bool = false;

// What a camera ray left: no primitive (a slot no scene reaches, and not DEAD).
const NO_ORIGIN: u32 = 0xfffffffeu;

// Half of f32's machine epsilon, 2^-24.
const UNIT_ROUNDOFF: f32 = 5.9604645e-8;

// γ(n): the bound on n successive roundings' relative error.
fn gamma(n: f32) -> f32 {
    return n * UNIT_ROUNDOFF / (1.0 - n * UNIT_ROUNDOFF);
}

struct SurfacePoint {
    p: vec3<f32>,
    // Rounding error bound per axis (0 with tmin).
    err: vec3<f32>,
}

// The point where `ray` meets `prim` at `t`.
fn surface_point(prim: Primitive, ray: Ray, t: f32) -> SurfacePoint {
    let p = ray.origin + ray.dir * t;
    if !RAY_ROBUST {
        return SurfacePoint(p, vec3<f32>(0.0));
    }
    if prim_is(prim.kind, PRIM_SPHERE) {
        // Reprojected onto the sphere.
        var l = p - prim.a;
        l = l * (prim.radius / length(l));
        return SurfacePoint(prim.a + l, abs(l) * gamma(6.0) + abs(prim.a) * gamma(2.0));
    }
    // Quad or triangle: a + α·b + β·c from the plane point's coordinates.
    let n = cross(prim.b, prim.c);
    let w = n / dot(n, n);
    let h = p - prim.a;
    let ab = prim.b * dot(w, cross(h, prim.c));
    let ac = prim.c * dot(w, cross(prim.b, h));
    return SurfacePoint(prim.a + ab + ac, (abs(prim.a) + abs(ab) + abs(ac)) * gamma(7.0));
}

// The next f32 towards +∞ (from 0: the smallest normal, which survives flush-to-zero).
fn next_float_up(v: f32) -> f32 {
    if v == 0.0 {
        return 1.17549435e-38;
    }
    let b = bitcast<u32>(v);
    return bitcast<f32>(select(b - 1u, b + 1u, v > 0.0));
}

fn next_float_down(v: f32) -> f32 {
    if v == 0.0 {
        return -1.17549435e-38;
    }
    let b = bitcast<u32>(v);
    return bitcast<f32>(select(b + 1u, b - 1u, v > 0.0));
}

// The origin of a ray leaving `sp` along `dir`, for the geometric unit normal `n`.
fn spawn_origin(sp: SurfacePoint, n: vec3<f32>, dir: vec3<f32>) -> vec3<f32> {
    if !RAY_ROBUST {
        return sp.p;
    }
    let d = dot(abs(n), sp.err);
    var offset = n * d;
    if dot(dir, n) < 0.0 {
        offset = -offset;
    }
    var po = sp.p + offset;
    for (var i = 0; i < 3; i++) {
        if offset[i] > 0.0 {
            po[i] = next_float_up(po[i]);
        } else if offset[i] < 0.0 {
            po[i] = next_float_down(po[i]);
        }
    }
    return po;
}

// A ray that left primitive `left` met primitive `hit` at `t` where leaving cannot meet it: any
// hit on the same quad or triangle, or on the same sphere nearer than half the chord.
fn is_self_hit(left: u32, hit: u32, ray: Ray, t: f32) -> bool {
    if left != hit {
        return false;
    }
    let p = primitive(hit);
    if !prim_is(p.kind, PRIM_SPHERE) {
        return true;
    }
    let half_chord = -dot(ray.origin - p.a, ray.dir);
    return !(half_chord > 0.0) || t < half_chord;
}

// Failure counters (binding `failures`), 64-bit as two words each: low word first.
const FAILURE_SELF_HIT: u32 = 0u;
const FAILURE_SHADOW_SELF_HIT: u32 = 1u;
const FAILURE_DEPTH_CUT: u32 = 2u;

fn count_failure(which: u32) {
    // The add that wraps the low word carries into the high one.
    if atomicAdd(&failures[2u * which], 1u) == 0xffffffffu {
        atomicAdd(&failures[2u * which + 1u], 1u);
    }
}
