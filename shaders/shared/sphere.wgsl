// Ray–sphere intersection; twin of src/cpu/sphere.rs (Ray Tracing Gems ch. 7 discriminant).
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

fn sphere_normal(s: Primitive, p: vec3<f32>) -> vec3<f32> {
    return (p - s.a) / s.radius;
}
