// A ray with a unit-length direction; twin of src/cpu/ray.rs.

struct Ray {
    origin: vec3<f32>,
    dir: vec3<f32>,
}
