//! Writing a scene back out in the format [`load`](super::load) reads.
//!
//! The writer is hand-rolled rather than `serde_json::to_string_pretty`, for two reasons:
//! - readability: one line per material and per object, vectors inline (serde_json's pretty
//!   printer would put every number of a 488-sphere scene on its own line);
//! - exact numbers: each f32 is written as its shortest decimal form (`0.3`, not the f64 widening
//!   `0.30000001192092896`), checked to read back to the identical f32 through serde_json's f64
//!   parser and `as f32`, so `load(to_json(scene)) == scene` bit for bit.

use std::fmt::Write as _;

use glam::Vec3;

use super::{Background, ImageSource, Material, MeshSource, Scene, Texture, FORMAT};

/// The scene as pretty-printed JSON: `format`, `camera`, `background`, `materials` (in scene
/// order), `objects` (spheres, quads, then meshes by their absolute OBJ path or terrain size; a glTF
/// primitive by its file and path, which no scene file can load). Objects name their material.
///
/// Expects a scene that passes [`Scene::validate`]: a non-finite number is written as `null` and
/// an out-of-range material index as a name no material has, so such a file fails to load with
/// an error at the right path rather than loading as something else.
pub fn to_json(scene: &Scene) -> String {
    let mut out = String::with_capacity(256 + 96 * (scene.materials.len() + scene.spheres.len()));
    // Writing to a String cannot fail; each `let _` discards the Ok.
    let _ = writeln!(out, "{{\n  \"format\": {},", string(FORMAT));

    let c = &scene.camera;
    let _ = writeln!(out, "  \"camera\": {{");
    let _ = writeln!(out, "    \"lookfrom\": {},", vec3(c.lookfrom));
    let _ = writeln!(out, "    \"lookat\": {},", vec3(c.lookat));
    let _ = writeln!(out, "    \"vup\": {},", vec3(c.vup));
    let _ = writeln!(out, "    \"vfov\": {},", number(c.vfov));
    let _ = writeln!(out, "    \"defocus_angle\": {},", number(c.defocus_angle));
    let _ = writeln!(out, "    \"focus_dist\": {}", number(c.focus_dist));
    let _ = writeln!(out, "  }},");

    let background = match scene.background {
        Background::Sky => r#"{"type": "sky"}"#.to_owned(),
        Background::Constant(color) => {
            format!(r#"{{"type": "constant", "color": {}}}"#, vec3(color))
        }
    };
    let _ = writeln!(out, "  \"background\": {background},");

    let materials = scene.materials.iter().map(|m| {
        let kind = string(m.material.kind_name());
        let fields = match m.material {
            Material::Lambertian { albedo } => format!(r#""albedo": {}"#, texture(&albedo, scene)),
            Material::Metal { albedo, fuzz } => {
                format!(r#""albedo": {}, "fuzz": {}"#, texture(&albedo, scene), number(fuzz))
            }
            Material::Dielectric { ior } => format!(r#""ior": {}"#, number(ior)),
            Material::Emissive { radiance } => format!(r#""radiance": {}"#, vec3(radiance)),
        };
        format!(r#"{}: {{"type": {kind}, {fields}}}"#, string(&m.name))
    });
    block(&mut out, "materials", ('{', '}'), materials);
    out.push_str(",\n");

    let material = |m: u32| match scene.materials.get(m as usize) {
        Some(m) => string(&m.name),
        None => string(&format!("<missing material #{m}>")),
    };
    let spheres = scene.spheres.iter().map(|s| {
        format!(
            r#"{{"type": "sphere", "center": {}, "radius": {}, "material": {}}}"#,
            vec3(s.center),
            number(s.radius),
            material(s.material)
        )
    });
    let quads = scene.quads.iter().map(|q| {
        format!(
            r#"{{"type": "quad", "corner": {}, "u": {}, "v": {}, "material": {}}}"#,
            vec3(q.corner),
            vec3(q.u),
            vec3(q.v),
            material(q.material)
        )
    });
    let meshes = scene.meshes.iter().map(|m| match &m.source {
        MeshSource::File(file) => format!(
            r#"{{"type": "mesh", "file": {}, "material": {}}}"#,
            string(&file.to_string_lossy()),
            material(m.material)
        ),
        MeshSource::Terrain(n) => {
            format!(r#"{{"type": "mesh", "terrain": {n}, "material": {}}}"#, material(m.material))
        }
        // Scene files cannot refer to a glTF primitive: this names it (so the text identifies
        // the scene, as reference-cache keys need) and fails to load at `gltf`.
        MeshSource::Gltf { file, primitive } => format!(
            r#"{{"type": "mesh", "gltf": {}, "primitive": {}, "material": {}}}"#,
            string(&file.to_string_lossy()),
            string(primitive),
            material(m.material)
        ),
    });
    let objects = spheres.chain(quads).chain(meshes);
    block(&mut out, "objects", ('[', ']'), objects);
    out.push_str("\n}\n");
    out
}

/// `  "key": [` + one item per line + `  ]` (or `[]` when empty), without a trailing newline.
fn block(out: &mut String, key: &str, (open, close): (char, char), items: impl Iterator<Item = String>) {
    let _ = write!(out, "  \"{key}\": {open}");
    let mut first = true;
    for item in items {
        out.push_str(if first { "\n    " } else { ",\n    " });
        out.push_str(&item);
        first = false;
    }
    if !first {
        out.push_str("\n  ");
    }
    out.push(close);
}

fn string(s: &str) -> String {
    serde_json::to_string(s).expect("a string always serialises")
}

fn vec3(v: Vec3) -> String {
    format!("[{}, {}, {}]", number(v.x), number(v.y), number(v.z))
}

/// The shortest decimal that reads back (JSON → f64 → `as f32`) as exactly `x`.
fn number(x: f32) -> String {
    if !x.is_finite() {
        return "null".into();
    }
    if x == 0.0 {
        // Keep the sign of -0.0: "-0" would parse as the integer 0.
        return if x.is_sign_negative() { "-0.0" } else { "0" }.into();
    }
    // Rust's `{}` / `{:e}` print the shortest digits that round-trip as f32; the plain form is
    // kept for everyday magnitudes, the exponent form avoids 40-digit literals.
    let short = if (1e-5..1e16).contains(&x.abs()) { format!("{x}") } else { format!("{x:e}") };
    if reads_back(&short, x) {
        return short;
    }
    // Reading through f64 rounds twice; should that ever land on the wrong f32, the exact f64
    // value of `x` is always read back right (it is an f32, far from any f32 rounding boundary).
    format!("{}", f64::from(x))
}

fn reads_back(text: &str, x: f32) -> bool {
    serde_json::from_str::<f64>(text).is_ok_and(|y| (y as f32).to_bits() == x.to_bits())
}

/// A solid albedo as `[r, g, b]` (as before textures existed), others as tagged objects; an
/// image by its absolute file, or, for a glTF file's image, by the file and the image's glTF
/// path (which, like a glTF primitive, no scene file can load: it fails at `gltf`).
fn texture(t: &Texture, scene: &Scene) -> String {
    let kind = string(t.kind_name());
    match *t {
        Texture::Solid(c) => vec3(c),
        Texture::Checker { scale, even, odd } => {
            format!(
                r#"{{"type": {kind}, "scale": {}, "even": {}, "odd": {}}}"#,
                number(scale),
                vec3(even),
                vec3(odd)
            )
        }
        Texture::Procedural { scale, octaves, color, .. } => format!(
            r#"{{"type": {kind}, "scale": {}, "octaves": {octaves}, "color": {}}}"#,
            number(scale),
            vec3(color)
        ),
        Texture::Image { image, wrap, tint } => {
            let source = match scene.images.get(image as usize).map(|im| &im.source) {
                Some(ImageSource::File(f)) => format!(r#""file": {}"#, string(&f.to_string_lossy())),
                Some(ImageSource::Gltf { file, image }) => {
                    format!(r#""gltf": {}, "image": {}"#, string(&file.to_string_lossy()), string(image))
                }
                None => format!(r#""file": {}"#, string(&format!("<missing image #{image}>"))),
            };
            format!(
                r#"{{"type": {kind}, {source}, "wrap": [{}, {}], "tint": {}}}"#,
                string(wrap[0].name()),
                string(wrap[1].name()),
                vec3(tint)
            )
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::pcg4d;

    #[test]
    fn numbers_are_short() {
        assert_eq!(number(0.3), "0.3");
        assert_eq!(number(1000.0), "1000");
        assert_eq!(number(-4.0), "-4");
        assert_eq!(number(0.0), "0");
        assert_eq!(number(-0.0), "-0.0");
        assert_eq!(number(1e30), "1e30");
        assert_eq!(number(1.5e-7), "1.5e-7");
        assert_eq!(number(f32::NAN), "null");
    }

    /// Every finite f32 we try reads back bit-identical, across the whole exponent range.
    #[test]
    fn numbers_round_trip_exactly() {
        let specials = [f32::MIN_POSITIVE, f32::MAX, f32::MIN, f32::EPSILON, 1e-45, -0.0, 0.1, 1.0 / 3.0];
        let random = (0..200_000u32).map(|i| f32::from_bits(pcg4d([i, 77, 0, 0])[0]));
        for x in specials.into_iter().chain(random).filter(|x| x.is_finite()) {
            let s = number(x);
            assert!(reads_back(&s, x), "{x:e} written as {s}");
            // The fallback form, never needed for these (nor for 2^26 more tried once), works too.
            assert!(reads_back(&f64::from(x).to_string(), x), "{x:e}");
        }
    }
}
