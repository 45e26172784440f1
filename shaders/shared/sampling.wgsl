// Warping uniform numbers to directions; twin of src/cpu/sampling.rs.

const PI: f32 = 3.14159265358979323846;

fn unit_vector(u1: f32, u2: f32) -> vec3<f32> {
    let z = 1.0 - 2.0 * u1;
    let r = sqrt(max(1.0 - z * z, 0.0));
    let phi = 2.0 * PI * u2;
    return vec3<f32>(r * cos(phi), r * sin(phi), z);
}

fn in_unit_disk(u1: f32, u2: f32) -> vec2<f32> {
    let r = sqrt(u1);
    let phi = 2.0 * PI * u2;
    return vec2<f32>(r * cos(phi), r * sin(phi));
}

// Two unit vectors completing unit `n` to an orthonormal frame (Duff et al., JCGT 2017).
fn orthonormal_basis(n: vec3<f32>) -> array<vec3<f32>, 2> {
    let sign = select(-1.0, 1.0, n.z >= 0.0);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    return array<vec3<f32>, 2>(
        vec3<f32>(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x),
        vec3<f32>(b, sign + n.y * n.y * a, -n.y),
    );
}
