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
