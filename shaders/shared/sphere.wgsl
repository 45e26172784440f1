// Ray–sphere intersection (Ray Tracing Gems ch. 7 discriminant, or the book's quadratic with
// --sphere-hit book), and sampling a sphere by the cone it subtends; twin of src/cpu/sphere.rs.

// Pipeline constant: `--sphere-hit book`.
override SPHERE_BOOK: bool = false;

// Distance to the nearest hit in (t_min, t_max) by the formula --sphere-hit chose, or -1.
fn hit_sphere_by(center: vec3<f32>, radius: f32, ray: Ray, t_min: f32, t_max: f32) -> f32 {
    if SPHERE_BOOK {
        return hit_sphere_book(center, radius, ray, t_min, t_max);
    }
    return hit_sphere(center, radius, ray, t_min, t_max);
}
// A sphere is a Primitive (shared/primitive.wgsl) with centre `a` and `radius`.

// Distance to the nearest intersection in (t_min, t_max), or -1 for none.
fn hit_sphere(center: vec3<f32>, radius: f32, ray: Ray, t_min: f32, t_max: f32) -> f32 {
    let f = ray.origin - center;
    let b = dot(f, ray.dir);
    let l = f - ray.dir * b;
    let disc = radius * radius - dot(l, l);
    if disc < 0.0 {
        return -1.0;
    }
    let c = dot(f, f) - radius * radius;
    let sq = sqrt(disc);
    var q: f32;
    if b >= 0.0 {
        q = -b - sq;
    } else {
        q = -b + sq;
    }
    if q == 0.0 {
        return -1.0;
    }
    let t0 = c / q;
    let t1 = q;
    var near = t1;
    var far = t0;
    if t0 < t1 {
        near = t0;
        far = t1;
    }
    if near > t_min && near < t_max {
        return near;
    }
    if far > t_min && far < t_max {
        return far;
    }
    return -1.0;
}

// The book's quadratic (--sphere-hit book); twin of hit_sphere_book in src/cpu/sphere.rs.
fn hit_sphere_book(center: vec3<f32>, radius: f32, ray: Ray, t_min: f32, t_max: f32) -> f32 {
    let oc = center - ray.origin;
    let a = dot(ray.dir, ray.dir);
    let h = dot(ray.dir, oc);
    let c = dot(oc, oc) - radius * radius;
    let disc = h * h - a * c;
    if disc < 0.0 {
        return -1.0;
    }
    let sq = sqrt(disc);
    let near = (h - sq) / a;
    if near > t_min && near < t_max {
        return near;
    }
    let far = (h + sq) / a;
    if far > t_min && far < t_max {
        return far;
    }
    return -1.0;
}

fn sphere_normal(s: Primitive, p: vec3<f32>) -> vec3<f32> {
    return (p - s.a) / s.radius;
}

// The cone of directions a sphere subtends from a point outside it.
struct Cone {
    // Unit direction from the point to the centre.
    axis: vec3<f32>,
    // sin² of the half-angle.
    sin2_max: f32,
    // 1 − cos of the half-angle, as sin²/(1 + cos).
    one_minus_cos_max: f32,
    // False: the point is not outside the sphere.
    ok: bool,
}

fn cone_solid_angle(c: Cone) -> f32 {
    return 2.0 * PI * c.one_minus_cos_max;
}

// The cone sphere `s` subtends from `x`.
fn sphere_cone(s: Primitive, x: vec3<f32>) -> Cone {
    let to = s.a - x;
    let dist2 = dot(to, to);
    let r2 = s.radius * s.radius;
    if !(dist2 > r2) {
        return Cone(vec3<f32>(0.0), 0.0, 0.0, false);
    }
    let sin2_max = r2 / dist2;
    let cos_max = sqrt(max(1.0 - sin2_max, 0.0));
    return Cone(to / sqrt(dist2), sin2_max, sin2_max / (1.0 + cos_max), true);
}

// The point of sphere `s` seen along a direction uniform in the cone `c` (pbrt-v4's
// Sphere::Sample); [0] the point, [1] its outward normal.
fn sample_cone(s: Primitive, c: Cone, u1: f32, u2: f32) -> array<vec3<f32>, 2> {
    let one_minus_cos = u1 * c.one_minus_cos_max;
    let cos_theta = 1.0 - one_minus_cos;
    let sin2_theta = one_minus_cos * (2.0 - one_minus_cos);
    let cos_alpha = sin2_theta / sqrt(c.sin2_max)
        + cos_theta * sqrt(max(1.0 - sin2_theta / c.sin2_max, 0.0));
    let sin_alpha = sqrt(max(1.0 - cos_alpha * cos_alpha, 0.0));
    let phi = 2.0 * PI * u2;
    let tb = orthonormal_basis(c.axis);
    let normal = -(tb[0] * (sin_alpha * cos(phi)) + tb[1] * (sin_alpha * sin(phi)) + c.axis * cos_alpha);
    return array<vec3<f32>, 2>(s.a + normal * s.radius, normal);
}
