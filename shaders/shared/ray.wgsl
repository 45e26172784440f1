// A ray with a unit-length direction; twin of src/cpu/ray.rs.

// Nearest intersections closer than this are ignored (the book's shadow-acne guard).
const T_MIN: f32 = 1e-3;

struct Ray {
    origin: vec3<f32>,
    dir: vec3<f32>,
}
