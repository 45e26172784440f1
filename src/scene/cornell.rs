//! `cornell`: the Cornell box of Ray Tracing: The Next Week ("Instances"), built from quads.
//!
//! Walls 0–555 on each axis (green at x = 555, red at x = 0, white floor, ceiling and back), the
//! light a 130×105 quad of radiance 15 just below the ceiling, and two white boxes, 165×330×165
//! rotated 15° about y and moved to (265, 0, 295), and 165×165×165 rotated −18° and moved to
//! (130, 0, 65). The book's `rotate_y` maps object to world space by x' = x cos θ + z sin θ,
//! z' = −x sin θ + z cos θ; the boxes' quads are transformed here once, so the renderer sees
//! plain quads. Camera at (278, 278, −800) looking at (278, 278, 0), vfov 40, pinhole, black
//! background: all light comes from the quad.

use glam::Vec3;

use super::{Background, CameraSpec, Material, NamedMaterial, Quad, Scene};

pub fn cornell() -> Scene {
    let lambertian = |name: &str, c: [f32; 3]| NamedMaterial {
        name: name.into(),
        material: Material::Lambertian { albedo: Vec3::from(c).into() },
    };
    let materials = vec![
        lambertian("red", [0.65, 0.05, 0.05]),
        lambertian("white", [0.73, 0.73, 0.73]),
        lambertian("green", [0.12, 0.45, 0.15]),
        NamedMaterial { name: "light".into(), material: Material::Emissive { radiance: Vec3::splat(15.0) } },
    ];
    let (red, white, green, light) = (0, 1, 2, 3);
    let q = |corner: [f32; 3], u: [f32; 3], v: [f32; 3], material| Quad {
        corner: corner.into(),
        u: u.into(),
        v: v.into(),
        material,
    };
    let mut quads = vec![
        q([555.0, 0.0, 0.0], [0.0, 555.0, 0.0], [0.0, 0.0, 555.0], green),
        q([0.0, 0.0, 0.0], [0.0, 555.0, 0.0], [0.0, 0.0, 555.0], red),
        q([343.0, 554.0, 332.0], [-130.0, 0.0, 0.0], [0.0, 0.0, -105.0], light),
        q([0.0, 0.0, 0.0], [555.0, 0.0, 0.0], [0.0, 0.0, 555.0], white),
        q([555.0, 555.0, 555.0], [-555.0, 0.0, 0.0], [0.0, 0.0, -555.0], white),
        q([0.0, 0.0, 555.0], [555.0, 0.0, 0.0], [0.0, 555.0, 0.0], white),
    ];
    quads.extend(rotated_box(Vec3::new(165.0, 330.0, 165.0), 15.0, Vec3::new(265.0, 0.0, 295.0), white));
    quads.extend(rotated_box(Vec3::splat(165.0), -18.0, Vec3::new(130.0, 0.0, 65.0), white));
    Scene {
        name: "cornell".into(),
        camera: CameraSpec {
            lookfrom: Vec3::new(278.0, 278.0, -800.0),
            lookat: Vec3::new(278.0, 278.0, 0.0),
            vup: Vec3::Y,
            vfov: 40.0,
            defocus_angle: 0.0,
            focus_dist: 10.0,
        },
        background: Background::Constant(Vec3::ZERO),
        materials,
        spheres: Vec::new(),
        quads,
        meshes: Vec::new(),
        images: Vec::new(),
    }
}

/// The book's `box(0, size)` (six quads, in its order), rotated about y by `degrees` and moved by
/// `offset`.
fn rotated_box(size: Vec3, degrees: f32, offset: Vec3, material: u32) -> Vec<Quad> {
    let (sin, cos) = degrees.to_radians().sin_cos();
    let rotate = |v: Vec3| Vec3::new(cos * v.x + sin * v.z, v.y, -sin * v.x + cos * v.z);
    let (min, max) = (Vec3::ZERO, size);
    let (dx, dy, dz) =
        (Vec3::new(size.x, 0.0, 0.0), Vec3::new(0.0, size.y, 0.0), Vec3::new(0.0, 0.0, size.z));
    let sides = [
        (Vec3::new(min.x, min.y, max.z), dx, dy),
        (Vec3::new(max.x, min.y, max.z), -dz, dy),
        (Vec3::new(max.x, min.y, min.z), -dx, dy),
        (Vec3::new(min.x, min.y, min.z), dz, dy),
        (Vec3::new(min.x, max.y, max.z), dx, -dz),
        (Vec3::new(min.x, min.y, min.z), dx, dz),
    ];
    sides
        .iter()
        .map(|&(corner, u, v)| Quad { corner: rotate(corner) + offset, u: rotate(u), v: rotate(v), material })
        .collect()
}
