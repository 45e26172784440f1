//! The scene file format: built-ins round-trip through export and load, and every kind of bad
//! input is refused with a message naming the file, the JSON path and the reason.

use std::path::PathBuf;

use glam::Vec3;
use wavetrace::scene::{
    builtin, export, load, Background, InputError, Material, NamedMaterial, Quad, Scene, Sphere, Texture,
    FORMAT,
};

/// A valid file using every material kind and a constant background; the bad cases below are
/// single edits of it.
const EXAMPLE: &str = include_str!("../scenes/example.json");

/// The number of spheres `rtiow-final` has with `RTIOW_FINAL_SEED`. A change here means the
/// layout changed: every figure rendered from it changes too.
const RTIOW_FINAL_SPHERES: usize = 486;

fn fixture(name: &str) -> PathBuf {
    crate::common::root().join("tests/scenes").join(name)
}

fn load_str(text: &str) -> Result<Scene, InputError> {
    load::from_str(text, "bad.json", "bad")
}

/// EXAMPLE with `from` (which must occur exactly once) replaced by `to`.
fn edit(from: &str, to: &str) -> String {
    assert_eq!(EXAMPLE.matches(from).count(), 1, "{from:?} must occur once in example.json");
    EXAMPLE.replacen(from, to, 1)
}

/// Loading `text` fails at `path` with a reason containing every one of `reason`.
#[track_caller]
fn assert_error(text: &str, path: &str, reason: &[&str]) {
    let err = match load_str(text) {
        Ok(_) => panic!("expected an error at {path:?}, but the scene loaded"),
        Err(e) => e,
    };
    assert_eq!(err.file, "bad.json", "{err}");
    assert_eq!(err.path, path, "{err}");
    for part in reason {
        assert!(err.reason.contains(part), "reason {:?} lacks {part:?}", err.reason);
    }
    let shown = err.to_string();
    let prefix = if path.is_empty() { "bad.json: ".to_owned() } else { format!("bad.json: {path}: ") };
    assert!(shown.starts_with(&prefix), "{shown}");
}

// ---------------------------------------------------------------------------------------------
// Valid files

#[test]
fn example_file_loads_as_written() {
    let scene = load::from_file(&fixture("example.json")).unwrap();
    assert_eq!(scene.name, "example");
    assert_eq!(scene.camera.lookat, Vec3::new(0.0, 0.5, 0.0));
    assert_eq!(scene.camera.defocus_angle, 0.25);
    assert_eq!(scene.background, Background::Constant(Vec3::new(0.1, 0.1, 0.15)));
    // File order is kept, including the unused material.
    let names: Vec<&str> = scene.materials.iter().map(|m| m.name.as_str()).collect();
    assert_eq!(names, ["floor", "red", "steel", "glass", "lamp", "unused"]);
    assert_eq!(
        scene.materials[2].material,
        Material::Metal { albedo: Vec3::new(0.7, 0.6, 0.5).into(), fuzz: 0.1 }
    );
    assert_eq!(scene.materials[4].material, Material::Emissive { radiance: Vec3::new(4.0, 4.0, 3.5) });
    let refs: Vec<u32> = scene.spheres.iter().map(|s| s.material).collect();
    assert_eq!(refs, [0, 1, 3, 2, 4]);
    assert_eq!(scene.spheres[0], Sphere { center: Vec3::new(0.0, -100.5, 0.0), radius: 100.0, material: 0 });
    assert_eq!(
        scene.material(&scene.spheres[3]),
        &Material::Metal { albedo: Vec3::new(0.7, 0.6, 0.5).into(), fuzz: 0.1 }
    );
}

#[test]
fn a_scene_without_objects_is_allowed() {
    let text = r#"{"format": "wavetrace-scene/1",
        "camera": {"lookfrom": [0, 0, 1], "lookat": [0, 0, 0], "vup": [0, 1, 0], "vfov": 90,
                   "defocus_angle": 0, "focus_dist": 1},
        "background": {"type": "sky"}, "materials": {}, "objects": []}"#;
    let scene = load::from_str(text, "<string>", "empty").unwrap();
    assert!(scene.spheres.is_empty() && scene.materials.is_empty());
    assert_eq!(scene.name, "empty");
    assert_eq!(load::from_str(&export::to_json(&scene), "<export>", "empty").unwrap(), scene);
}

#[test]
fn every_builtin_round_trips_through_export() {
    for &name in builtin::names() {
        let scene = builtin::by_name(name).unwrap();
        assert_eq!(scene.name, name);
        scene.validate().unwrap_or_else(|e| panic!("{name} is invalid: {e}"));
        let text = export::to_json(&scene);
        assert!(text.starts_with(&format!("{{\n  \"format\": \"{FORMAT}\",\n")), "{name}");
        let loaded = load::from_str(&text, &format!("<export of {name}>"), name)
            .unwrap_or_else(|e| panic!("exported {name} does not load: {e}"));
        assert_eq!(loaded, scene, "{name}");
        // Bit-identical, not just ==, and the writer is stable.
        assert_eq!(bits(&loaded), bits(&scene), "{name}");
        assert_eq!(export::to_json(&loaded), text, "{name}");
    }
}

#[test]
fn example_round_trips_and_keeps_numbers_readable() {
    let scene = load::from_file(&fixture("example.json")).unwrap();
    let text = export::to_json(&scene);
    assert!(text.contains(r#""steel": {"type": "metal", "albedo": [0.7, 0.6, 0.5], "fuzz": 0.1}"#), "{text}");
    assert!(text.contains(r#""background": {"type": "constant", "color": [0.1, 0.1, 0.15]}"#), "{text}");
    assert!(
        text.contains(r#"{"type": "sphere", "center": [0, -100.5, 0], "radius": 100, "material": "floor"}"#)
    );
    assert_eq!(load::from_str(&text, "<export>", "example").unwrap(), scene);
}

#[test]
fn awkward_values_round_trip_bit_exactly() {
    let mut scene = builtin::by_name("furnace").unwrap();
    let odd = [1.0 / 3.0, 1e-30, 3.4e38, f32::MIN_POSITIVE, 16_777_217.0, 0.1 + 0.2, -0.0, 1e-45];
    for (i, &x) in odd.iter().enumerate() {
        scene.spheres.push(Sphere { center: Vec3::new(x, -x, 0.5 * x), radius: 0.5 + i as f32, material: 0 });
    }
    scene.materials.push(NamedMaterial {
        name: "odd name \"with\" quotes / ünïcode".into(),
        material: Material::Metal { albedo: Vec3::new(1.0 / 3.0, 2.0 / 3.0, 0.1).into(), fuzz: 1.0 / 7.0 },
    });
    let loaded = load::from_str(&export::to_json(&scene), "<export>", "furnace").unwrap();
    assert_eq!(bits(&loaded), bits(&scene));
    assert_eq!(loaded.materials[1].name, "odd name \"with\" quotes / ünïcode");
}

/// Every f32 of a scene as bits, so -0.0 vs 0.0 or a last-bit change is caught.
fn bits(s: &Scene) -> Vec<u32> {
    let mut out = Vec::new();
    let v3 = |v: Vec3, out: &mut Vec<u32>| out.extend(v.to_array().map(f32::to_bits));
    let c = &s.camera;
    v3(c.lookfrom, &mut out);
    v3(c.lookat, &mut out);
    v3(c.vup, &mut out);
    out.extend([c.vfov, c.defocus_angle, c.focus_dist].map(f32::to_bits));
    if let Background::Constant(color) = s.background {
        v3(color, &mut out);
    }
    for m in &s.materials {
        match m.material {
            Material::Lambertian { albedo } => texture_bits(&albedo, &mut out),
            Material::Metal { albedo, fuzz } => {
                texture_bits(&albedo, &mut out);
                out.push(fuzz.to_bits());
            }
            Material::Dielectric { ior } => out.push(ior.to_bits()),
            Material::Emissive { radiance } => v3(radiance, &mut out),
        }
    }
    for sp in &s.spheres {
        v3(sp.center, &mut out);
        out.extend([sp.radius.to_bits(), sp.material]);
    }
    for q in &s.quads {
        for v in [q.corner, q.u, q.v] {
            v3(v, &mut out);
        }
        out.push(q.material);
    }
    out
}

fn texture_bits(t: &Texture, out: &mut Vec<u32>) {
    let v3 = |v: Vec3, out: &mut Vec<u32>| out.extend(v.to_array().map(f32::to_bits));
    match *t {
        Texture::Solid(c) => v3(c, out),
        Texture::Checker { scale, even, odd } => {
            out.push(scale.to_bits());
            v3(even, out);
            v3(odd, out);
        }
        Texture::Procedural { pattern, scale, octaves, color } => {
            out.extend([pattern.kind(), scale.to_bits(), octaves]);
            v3(color, out);
        }
        Texture::Image { image, wrap, tint } => {
            out.extend([image, wrap[0].code(), wrap[1].code()]);
            v3(tint, out);
        }
    }
}

#[test]
fn textures_load_export_and_round_trip() {
    let text = edit(
        r#""albedo": [0.8, 0.3, 0.3]"#,
        r#""albedo": {"type": "checker", "scale": 0.25, "even": [0.2, 0.3, 0.1], "odd": [0.9, 0.9, 0.9]}"#,
    )
    .replacen(
        r#""albedo": [0.7, 0.6, 0.5]"#,
        r#""albedo": {"type": "marble", "scale": 4, "octaves": 7, "color": [1, 1, 1]}"#,
        1,
    );
    let scene = load_str(&text).unwrap();
    let red = scene.materials.iter().find(|m| m.name == "red").unwrap();
    assert_eq!(
        red.material,
        Material::Lambertian {
            albedo: Texture::Checker { scale: 0.25, even: Vec3::new(0.2, 0.3, 0.1), odd: Vec3::splat(0.9) }
        }
    );
    let steel = scene.materials.iter().find(|m| m.name == "steel").unwrap();
    assert_eq!(steel.material, Material::Metal { albedo: Texture::marble(4.0, 7, Vec3::ONE), fuzz: 0.1 });
    let exported = export::to_json(&scene);
    assert!(
        exported.contains(r#"{"type": "marble", "scale": 4, "octaves": 7, "color": [1, 1, 1]}"#),
        "{exported}"
    );
    let again = load::from_str(&exported, "<export>", "bad").unwrap();
    assert_eq!(bits(&again), bits(&scene));
    // {"type": "solid"} is the long form of a plain colour.
    let solid =
        edit(r#""albedo": [0.8, 0.3, 0.3]"#, r#""albedo": {"type": "solid", "color": [0.8, 0.3, 0.3]}"#);
    assert_eq!(load_str(&solid).unwrap(), load_str(EXAMPLE).unwrap());
    let noise = edit(
        r#""albedo": [0.8, 0.3, 0.3]"#,
        r#""albedo": {"type": "noise", "scale": 2, "octaves": 1, "color": [1, 1, 1]}"#,
    );
    assert!(matches!(
        load_str(&noise).unwrap().materials.iter().find(|m| m.name == "red").unwrap().material,
        Material::Lambertian {
            albedo: Texture::Procedural { pattern: wavetrace::scene::Pattern::Noise, octaves: 1, .. }
        }
    ));
}

#[test]
fn bad_textures_are_refused_with_their_path() {
    let with = |texture: &str| edit(r#""albedo": [0.8, 0.3, 0.3]"#, &format!(r#""albedo": {texture}"#));
    assert_error(
        &with(r#"{"type": "marble", "scale": 4, "octaves": 0, "color": [1, 1, 1]}"#),
        "materials.red.albedo.octaves",
        &["must be in 1..=16, got 0"],
    );
    assert_error(
        &with(r#"{"type": "noise", "scale": 4, "octaves": 17, "color": [1, 1, 1]}"#),
        "materials.red.albedo.octaves",
        &["must be in 1..=16, got 17"],
    );
    assert_error(
        &with(r#"{"type": "noise", "scale": 4, "octaves": 2.5, "color": [1, 1, 1]}"#),
        "materials.red.albedo.octaves",
        &["expected a whole number"],
    );
    assert_error(
        &with(r#"{"type": "checker", "scale": 0, "even": [1, 1, 1], "odd": [0, 0, 0]}"#),
        "materials.red.albedo.scale",
        &["must be > 0, got 0"],
    );
    assert_error(
        &with(r#"{"type": "checker", "scale": 1, "even": [1, -1, 1], "odd": [0, 0, 0]}"#),
        "materials.red.albedo.even[1]",
        &["must be >= 0"],
    );
    assert_error(
        &with(r#"{"type": "marbel", "scale": 4, "octaves": 3, "color": [1, 1, 1]}"#),
        "materials.red.albedo.type",
        &["unknown texture type \"marbel\"", "did you mean \"marble\""],
    );
    assert_error(
        &with(r#"{"type": "noise", "scale": 4, "octaves": 3, "colour": [1, 1, 1]}"#),
        "materials.red.albedo.colour",
        &["unknown field", "did you mean \"color\""],
    );
    assert_error(
        &with(r#"{"type": "noise", "scale": 4, "color": [1, 1, 1]}"#),
        "materials.red.albedo",
        &["missing required field \"octaves\""],
    );
}

// ---------------------------------------------------------------------------------------------
// Built-in scenes

#[test]
fn rtiow_final_has_a_fixed_deterministic_layout() {
    let scene = builtin::by_name("rtiow-final").unwrap();
    assert!((450..=490).contains(&scene.spheres.len()));
    assert_eq!(scene.spheres.len(), RTIOW_FINAL_SPHERES);
    assert_eq!(scene.materials.len(), scene.spheres.len(), "one material per sphere");
    assert_eq!(builtin::by_name("rtiow-final").unwrap(), scene);

    let ground = scene.spheres[0];
    assert_eq!((ground.center, ground.radius), (Vec3::new(0.0, -1000.0, 0.0), 1000.0));
    assert_eq!(scene.materials[0].material, Material::Lambertian { albedo: Vec3::splat(0.5).into() });
    let big: Vec<(Vec3, &Material)> =
        scene.spheres[scene.spheres.len() - 3..].iter().map(|s| (s.center, scene.material(s))).collect();
    assert_eq!(
        big,
        [
            (Vec3::new(0.0, 1.0, 0.0), &Material::Dielectric { ior: 1.5 }),
            (Vec3::new(-4.0, 1.0, 0.0), &Material::Lambertian { albedo: Vec3::new(0.4, 0.2, 0.1).into() }),
            (
                Vec3::new(4.0, 1.0, 0.0),
                &Material::Metal { albedo: Vec3::new(0.7, 0.6, 0.5).into(), fuzz: 0.0 }
            ),
        ]
    );
    for s in &scene.spheres[1..scene.spheres.len() - 3] {
        assert_eq!((s.radius, s.center.y), (0.2, 0.2));
        assert!(s.center.distance(Vec3::new(4.0, 0.2, 0.0)) > 0.9);
        assert!((-11.0..11.0).contains(&s.center.x) && (-11.0..11.0).contains(&s.center.z));
    }
    let cam = &scene.camera;
    assert_eq!((cam.lookfrom, cam.lookat, cam.vup), (Vec3::new(13.0, 2.0, 3.0), Vec3::ZERO, Vec3::Y));
    assert_eq!((cam.vfov, cam.defocus_angle, cam.focus_dist), (20.0, 0.6, 10.0));
    assert_eq!(scene.background, Background::Sky);
}

#[test]
fn three_spheres_and_furnace_are_as_described() {
    let three = builtin::by_name("three-spheres").unwrap();
    let fin = builtin::by_name("rtiow-final").unwrap();
    assert_eq!(three.spheres.len(), 4);
    assert_eq!(three.camera, fin.camera);
    let names: Vec<&str> = three.materials.iter().map(|m| m.name.as_str()).collect();
    assert_eq!(names, ["ground", "glass", "brown", "mirror"]);

    let furnace = builtin::by_name("furnace").unwrap();
    assert_eq!(furnace.background, Background::Constant(Vec3::ONE));
    assert_eq!(furnace.camera.defocus_angle, 0.0);
    assert_eq!(furnace.spheres.len(), 1);
    assert_eq!(
        furnace.material(&furnace.spheres[0]),
        &Material::Lambertian { albedo: Vec3::splat(0.5).into() }
    );
    // The sphere fills part of the frame, not all of it.
    let s = furnace.spheres[0];
    let half_angle = (s.radius / furnace.camera.lookfrom.distance(s.center)).asin().to_degrees();
    assert!(half_angle > 0.25 * furnace.camera.vfov && half_angle < 0.45 * furnace.camera.vfov);

    assert_eq!(builtin::list().len(), builtin::names().len());
    assert!(builtin::list().iter().all(|(_, d)| !d.is_empty()));
}

#[test]
fn resolve_prefers_builtins_then_files() {
    assert_eq!(Scene::resolve("furnace").unwrap().name, "furnace");
    let path = fixture("example.json");
    assert_eq!(Scene::resolve(path.to_str().unwrap()).unwrap().name, "example");
}

// ---------------------------------------------------------------------------------------------
// Files that must be refused

#[test]
fn unreadable_files_name_the_file_and_the_os_reason() {
    let path = fixture("does-not-exist.json");
    let err = load::from_file(&path).unwrap_err();
    assert_eq!(err.file, path.display().to_string());
    assert_eq!(err.path, "");
    assert!(err.reason.starts_with("cannot read the file: "), "{err}");
    assert!(err.reason.contains("os error"), "{err}");
    let err = load::from_file(&fixture("")).unwrap_err(); // a directory
    assert!(err.reason.starts_with("cannot read the file: "), "{err}");
}

#[test]
fn errors_from_files_name_the_file() {
    let path = fixture("bad-radius.json");
    let err = load::from_file(&path).unwrap_err();
    assert_eq!(err.file, path.display().to_string());
    assert_eq!(err.path, "objects[0].radius");
    assert_eq!(err.reason, "must be > 0, got -1");
    assert_eq!(err.to_string(), format!("{}: objects[0].radius: must be > 0, got -1", path.display()));
}

#[test]
fn malformed_json_gives_line_and_column() {
    assert_error(&edit("\"vfov\": 35,", "\"vfov\": 35"), "", &["malformed JSON", "line 8 column 5"]);
    assert_error("", "", &["malformed JSON", "EOF", "line 1 column 0"]);
    assert_error(&format!("{EXAMPLE} {{}}"), "", &["malformed JSON", "trailing characters"]);
    assert_error(
        &edit("\"radius\": 100,", "\"radius\": 1e400,"),
        "",
        &["malformed JSON: number out of range", "line 21"],
    );
    assert_error("[1, 2, 3]", "", &["expected an object, found an array of 3 values"]);
}

#[test]
fn the_format_field_is_required_and_checked() {
    assert_error(&edit("\"format\": \"wavetrace-scene/1\",", ""), "", &["missing required field \"format\""]);
    assert_error(
        &edit("wavetrace-scene/1", "wavetrace-scene/2"),
        "format",
        &["unsupported format \"wavetrace-scene/2\"", "this build reads \"wavetrace-scene/1\""],
    );
    assert_error(&edit("\"wavetrace-scene/1\"", "1"), "format", &["expected a string, found a number (1)"]);
    // A newer version is reported as such, before its unknown fields.
    let newer =
        edit("\"format\": \"wavetrace-scene/1\",", "\"format\": \"wavetrace-scene/9\", \"lights\": [],");
    assert_error(&newer, "format", &["unsupported format"]);
}

#[test]
fn missing_fields_are_named() {
    assert_error(&edit("\"vfov\": 35,", ""), "camera", &["missing required field \"vfov\""]);
    assert_error(&edit(", \"fuzz\": 0.1", ""), "materials.steel", &["missing required field \"fuzz\""]);
    assert_error(&edit("\"radius\": 0.75, ", ""), "objects[4]", &["missing required field \"radius\""]);
    assert_error(
        &edit("\"type\": \"dielectric\", \"ior\": 1.5", "\"ior\": 1.5"),
        "materials.glass",
        &["missing required field \"type\""],
    );
    assert_error(
        &edit(", \"color\": [0.1, 0.1, 0.15]", ""),
        "background",
        &["missing required field \"color\""],
    );
    let no_bg = edit("\"background\": {\"type\": \"constant\", \"color\": [0.1, 0.1, 0.15]},", "");
    assert_error(&no_bg, "", &["missing required field \"background\""]);
}

#[test]
fn unknown_fields_are_rejected_with_a_hint() {
    assert_error(
        &edit("\"radius\": 0.75", "\"radus\": 0.75"),
        "objects[4].radus",
        &[
            "unknown field (did you mean \"radius\"?)",
            "expected \"type\", \"center\", \"radius\" or \"material\"",
        ],
    );
    assert_error(
        &edit("\"focus_dist\": 5", "\"focus_dist\": 5, \"aperture\": 0.1"),
        "camera.aperture",
        &["unknown field"],
    );
    // A field that belongs to another material type is still unknown here.
    assert_error(
        &edit("\"ior\": 1.5", "\"ior\": 1.5, \"fuzz\": 0"),
        "materials.glass.fuzz",
        &["unknown field", "expected \"type\" or \"ior\""],
    );
    assert_error(&edit("\"objects\"", "\"lights\": [], \"objects\""), "lights", &["unknown field"]);
    assert_error(
        &edit("{\"type\": \"constant\"", "{\"type\": \"sky\""),
        "background.color",
        &["unknown field"],
    );
}

#[test]
fn wrong_types_say_what_was_expected() {
    assert_error(
        &edit("[0.8, 0.3, 0.3]", "[0.8, 0.3]"),
        "materials.red.albedo",
        &["expected an array of 3 numbers, found an array of 2 values"],
    );
    assert_error(
        &edit("[0.8, 0.3, 0.3]", "\"red\""),
        "materials.red.albedo",
        &["expected an array of 3 numbers, found a string (\"red\")"],
    );
    assert_error(
        &edit("[0.8, 0.3, 0.3]", "[0.8, \"0.3\", 0.3]"),
        "materials.red.albedo[1]",
        &["expected a number, found a string (\"0.3\")"],
    );
    assert_error(&edit("\"vfov\": 35", "\"vfov\": null"), "camera.vfov", &["expected a number, found null"]);
    assert_error(
        &edit("\"radius\": 0.75", "\"radius\": [0.75]"),
        "objects[4].radius",
        &["expected a number, found an array of 1 value"],
    );
    assert_error(
        &edit("\"material\": \"lamp\"", "\"material\": 4"),
        "objects[4].material",
        &["expected a string"],
    );
    assert_error(&edit("\"lookat\": [0, 0.5, 0]", "\"lookat\": {}"), "camera.lookat", &["found an object"]);
    assert_error(
        &edit("\"type\": \"dielectric\", \"ior\": 1.5", "\"type\": true, \"ior\": 1.5"),
        "materials.glass.type",
        &["expected a string, found a boolean (true)"],
    );
    let objects_as_map = r#"{"format": "wavetrace-scene/1", "camera": {"lookfrom": [0, 0, 1], "lookat": [0, 0, 0],
        "vup": [0, 1, 0], "vfov": 90, "defocus_angle": 0, "focus_dist": 1}, "background": {"type": "sky"},
        "materials": [], "objects": {}}"#;
    assert_error(objects_as_map, "materials", &["expected an object, found an array of 0 values"]);
    assert_error(
        &objects_as_map.replace("\"materials\": []", "\"materials\": {}"),
        "objects",
        &["expected an array of objects, found an object"],
    );
    assert_error(
        &edit("\"objects\": [", "\"objects\": [3,"),
        "objects[0]",
        &["expected an object, found a number (3)"],
    );
}

#[test]
fn numbers_must_be_finite_as_f32() {
    assert_error(
        &edit("\"radius\": 100,", "\"radius\": 1e39,"),
        "objects[0].radius",
        &["not a finite number"],
    );
    // Huge but within f32 range: finite, so the sign check is what refuses it.
    assert_error(&edit("[4, 4, 3.5]", "[4, 4, -3e38]"), "materials.lamp.radiance[2]", &["must be >= 0"]);
    assert_error(
        &edit("[4, 4, 3.5]", "[4, 4, -3.5e38]"),
        "materials.lamp.radiance[2]",
        &["not a finite number"],
    );
    assert_error(
        &edit("[4, 4, 3.5]", "[4, 4, -1e300]"),
        "materials.lamp.radiance[2]",
        &["not a finite number"],
    );
    // 1e-50 underflows to 0, which is a finite f32, so it is a value check that refuses it.
    assert_error(&edit("\"ior\": 1.5", "\"ior\": 1e-50"), "materials.glass.ior", &["must be > 0, got 0"]);
}

#[test]
fn out_of_range_values_are_refused() {
    assert_error(&edit("\"radius\": 0.75", "\"radius\": 0"), "objects[4].radius", &["must be > 0, got 0"]);
    assert_error(
        &edit("\"radius\": 0.75", "\"radius\": -0.75"),
        "objects[4].radius",
        &["must be > 0, got -0.75"],
    );
    assert_error(
        &edit("\"fuzz\": 0.1", "\"fuzz\": 1.5"),
        "materials.steel.fuzz",
        &["must be in [0, 1], got 1.5"],
    );
    assert_error(&edit("\"fuzz\": 0.1", "\"fuzz\": -0.1"), "materials.steel.fuzz", &["must be in [0, 1]"]);
    assert_error(&edit("\"ior\": 1.5", "\"ior\": 0"), "materials.glass.ior", &["must be > 0, got 0"]);
    assert_error(&edit("\"ior\": 0.67", "\"ior\": -1.5"), "materials.unused.ior", &["must be > 0, got -1.5"]);
    assert_error(
        &edit("[0.8, 0.3, 0.3]", "[0.8, -0.3, 0.3]"),
        "materials.red.albedo[1]",
        &["must be >= 0, got -0.3"],
    );
    assert_error(
        &edit("[0.7, 0.6, 0.5]", "[-0.7, 0.6, 0.5]"),
        "materials.steel.albedo[0]",
        &["must be >= 0"],
    );
    assert_error(
        &edit("[4, 4, 3.5]", "[4, 4, -3.5]"),
        "materials.lamp.radiance[2]",
        &["must be >= 0, got -3.5"],
    );
    assert_error(&edit("[0.1, 0.1, 0.15]", "[0.1, -0.1, 0.15]"), "background.color[1]", &["must be >= 0"]);
    for vfov in ["0", "180", "-10", "200"] {
        assert_error(
            &edit("\"vfov\": 35", &format!("\"vfov\": {vfov}")),
            "camera.vfov",
            &["must be in (0, 180) degrees"],
        );
    }
    for angle in ["-1", "180"] {
        assert_error(
            &edit("\"defocus_angle\": 0.25", &format!("\"defocus_angle\": {angle}")),
            "camera.defocus_angle",
            &["must be in [0, 180) degrees"],
        );
    }
    assert_error(
        &edit("\"focus_dist\": 5", "\"focus_dist\": 0"),
        "camera.focus_dist",
        &["must be > 0, got 0"],
    );
    assert_error(
        &edit("\"lookat\": [0, 0.5, 0]", "\"lookat\": [0, 1, 5]"),
        "camera.lookat",
        &["equals camera.lookfrom"],
    );
    assert_error(
        &edit("\"vup\": [0, 1, 0]", "\"vup\": [0, -1, -10]"),
        "camera.vup",
        &["parallel (or nearly) to the view direction"],
    );
    assert_error(
        &edit("\"vup\": [0, 1, 0]", "\"vup\": [0, 0, 0]"),
        "camera.vup",
        &["must not be the zero vector"],
    );
    // Nearly but not quite parallel (about 0.01 degrees) is still a usable camera.
    assert!(load_str(&edit("\"vup\": [0, 1, 0]", "\"vup\": [0.001, -0.5, -5]")).is_ok());
}

#[test]
fn names_and_types_must_resolve() {
    assert_error(
        &edit("\"material\": \"red\"", "\"material\": \"rde\""),
        "objects[1].material",
        &[
            "unknown material \"rde\" (did you mean \"red\"?)",
            "defined materials: \"floor\", \"red\", \"steel\", \"glass\", \"lamp\", \"unused\"",
        ],
    );
    assert_error(
        &edit("\"material\": \"red\"", "\"material\": \"chrome\""),
        "objects[1].material",
        &["unknown material \"chrome\"; defined materials:"],
    );
    assert_error(
        &edit("\"type\": \"lambertian\", \"albedo\": [0.8", "\"type\": \"lambertain\", \"albedo\": [0.8"),
        "materials.red.type",
        &[
            "unknown material type \"lambertain\" (did you mean \"lambertian\"?)",
            "expected \"lambertian\", \"metal\", \"dielectric\" or \"emissive\"",
        ],
    );
    assert_error(
        &edit("{\"type\": \"sphere\", \"center\": [0, 3, 0]", "{\"type\": \"cube\", \"center\": [0, 3, 0]"),
        "objects[4].type",
        &["unknown object type \"cube\"; expected \"sphere\""],
    );
    assert_error(
        &edit("\"type\": \"constant\"", "\"type\": \"gradient\""),
        "background.type",
        &["unknown background type \"gradient\"; expected \"sky\" or \"constant\""],
    );
    assert_error(&edit("\"unused\":", "\"\":"), "materials[\"\"]", &["material name must not be empty"]);
}

#[test]
fn duplicate_keys_are_refused() {
    let dup = edit(
        "\"unused\": {\"type\": \"dielectric\", \"ior\": 0.67}",
        "\"red\": {\"type\": \"dielectric\", \"ior\": 0.67}",
    );
    assert_error(&dup, "materials.red", &["duplicate key \"red\"", "line 18", "only once"]);
    assert_error(
        &edit("\"radius\": 0.75", "\"radius\": 0.75, \"radius\": 1"),
        "objects[4].radius",
        &["duplicate key"],
    );
}

#[test]
fn material_names_that_need_quoting_are_quoted_in_paths() {
    let text = EXAMPLE.replace("\"steel\"", "\"brushed steel\"");
    let text = text.replace("\"fuzz\": 0.1", "\"fuzz\": 2");
    assert_error(&text, "materials[\"brushed steel\"].fuzz", &["must be in [0, 1]"]);
}

#[test]
fn scenes_built_in_code_are_validated_too() {
    let mut scene = builtin::by_name("three-spheres").unwrap();
    scene.spheres[2].material = 9;
    let err = scene.validate().unwrap_err();
    assert_eq!((err.file.as_str(), err.path.as_str()), ("<scene three-spheres>", "objects[2].material"));
    assert!(err.reason.contains("material index 9, but the scene has 4 materials"), "{err}");
    // Exporting an invalid scene gives a file that fails to load, at the same place.
    let err = load_str(&export::to_json(&scene)).unwrap_err();
    assert_eq!(err.path, "objects[2].material");

    let mut scene = builtin::by_name("three-spheres").unwrap();
    scene.materials[3].material = Material::Metal { albedo: Vec3::ONE.into(), fuzz: f32::NAN };
    let err = scene.validate().unwrap_err();
    assert_eq!(err.path, "materials.mirror.fuzz");
    assert!(err.reason.contains("not a finite number"), "{err}");
    assert_eq!(load_str(&export::to_json(&scene)).unwrap_err().path, "materials.mirror.fuzz");

    let mut scene = builtin::by_name("three-spheres").unwrap();
    scene.materials[2].name = "glass".into();
    let err = scene.validate().unwrap_err();
    assert_eq!(err.path, "materials.glass");
    assert!(err.reason.contains("duplicate material name"), "{err}");
}

// ---------------------------------------------------------------------------------------------
// No panics

#[test]
fn every_truncation_is_an_error_not_a_panic() {
    for text in [EXAMPLE.to_owned(), export::to_json(&builtin::by_name("three-spheres").unwrap())] {
        let end = text.trim_end().len();
        for cut in (0..end).filter(|&i| text.is_char_boundary(i)) {
            assert!(load_str(&text[..cut]).is_err(), "truncated at {cut} loaded");
        }
    }
    let big = export::to_json(&builtin::by_name("rtiow-final").unwrap());
    for cut in (0..big.trim_end().len()).step_by(61) {
        assert!(load_str(&big[..cut]).is_err(), "truncated at {cut} loaded");
    }
}

#[test]
fn single_byte_edits_never_panic() {
    // Each byte replaced by each of a few troublesome characters: a result either way, no panic.
    let bytes = EXAMPLE.as_bytes();
    let mut refused = 0;
    for i in 0..bytes.len() {
        for c in [b'x', b'-', b'0', b'9', b'"', b'[', b'}', b',', b' ', b'e'] {
            let mut edited = bytes.to_vec();
            edited[i] = c;
            if let Ok(text) = std::str::from_utf8(&edited) {
                refused += usize::from(load_str(text).is_err());
            }
        }
    }
    assert!(refused > bytes.len(), "most edits should be refused");
}

// ---------------------------------------------------------------------------------------------
// Quads and meshes

/// A quad and a mesh added to the example's objects.
fn with_objects(extra: &str) -> String {
    edit(
        r#"{"type": "sphere", "center": [0, 3, 0], "radius": 0.75, "material": "lamp"}"#,
        &format!(r#"{{"type": "sphere", "center": [0, 3, 0], "radius": 0.75, "material": "lamp"}}, {extra}"#),
    )
}

#[test]
fn quads_and_meshes_load_in_file_order_and_round_trip() {
    let dir = std::env::temp_dir().join(format!("wavetrace-mesh-{}", std::process::id()));
    std::fs::create_dir_all(dir.join("meshes")).unwrap();
    std::fs::write(dir.join("meshes/tri.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 4 3\n").unwrap();
    let text = with_objects(
        r#"{"type": "mesh", "file": "meshes/tri.obj", "material": "red"},
           {"type": "quad", "corner": [1, 2, 3], "u": [0.5, 0, 0], "v": [0, 0, 0.25], "material": "lamp"}"#,
    );
    std::fs::write(dir.join("scene.json"), &text).unwrap();
    let scene = load::from_file(&dir.join("scene.json")).unwrap();
    assert_eq!(
        scene.quads,
        [Quad {
            corner: Vec3::new(1.0, 2.0, 3.0),
            u: Vec3::new(0.5, 0.0, 0.0),
            v: Vec3::new(0.0, 0.0, 0.25),
            material: 4
        }]
    );
    assert_eq!(scene.meshes.len(), 1);
    let mesh = &scene.meshes[0];
    assert_eq!(mesh.triangles.len(), 2, "one quad face fans into two triangles");
    assert_eq!(mesh.material, 1);
    let wavetrace::scene::MeshSource::File(file) = &mesh.source else { panic!("{:?}", mesh.source) };
    assert!(file.is_absolute() && file.ends_with("meshes/tri.obj"), "{file:?}");
    // Written anywhere, the export still finds its mesh (absolute path) and loads unchanged.
    let exported = export::to_json(&scene);
    std::fs::create_dir_all(dir.join("elsewhere")).unwrap();
    std::fs::write(dir.join("elsewhere/copy.json"), &exported).unwrap();
    let mut again = load::from_file(&dir.join("elsewhere/copy.json")).unwrap();
    again.name = scene.name.clone();
    assert_eq!(again, scene);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn bad_quads_and_meshes_are_refused_with_their_path() {
    let quad = |u: &str, v: &str| {
        with_objects(&format!(
            r#"{{"type": "quad", "corner": [0, 0, 0], "u": {u}, "v": {v}, "material": "red"}}"#
        ))
    };
    // objects[5] is the first added object.
    assert_error(&quad("[0, 0, 0]", "[0, 1, 0]"), "objects[5].u", &["zero vector", "degenerate"]);
    assert_error(&quad("[1, 0, 0]", "[0, 0, 0]"), "objects[5].v", &["zero vector", "degenerate"]);
    assert_error(&quad("[1, 0, 0]", "[2, 0, 0]"), "objects[5].v", &["parallel", "degenerate"]);
    assert_error(&quad("[1, 0, 0]", "[1, 1e-9, 0]"), "objects[5].v", &["parallel"]);
    assert_error(&quad("[1, 0, 0]", "[0, 1]"), "objects[5].v", &["expected an array of 3 numbers"]);
    assert_error(
        &with_objects(
            r#"{"type": "quad", "corner": [0, 0, 0], "u": [1, 0, 0], "v": [0, 1, 0], "material": "nope"}"#,
        ),
        "objects[5].material",
        &["unknown material \"nope\""],
    );
    assert_error(
        &with_objects(r#"{"type": "quad", "corner": [0, 0, 0], "u": [1, 0, 0], "v": [0, 1, 0]}"#),
        "objects[5]",
        &["missing required field \"material\""],
    );
    assert_error(
        &with_objects(r#"{"type": "quadd", "corner": [0, 0, 0]}"#),
        "objects[5].type",
        &["unknown object type \"quadd\"", "did you mean \"quad\"", "\"mesh\""],
    );

    // Meshes: the OBJ's problems carry the field's path, the OBJ's name and, where it has one,
    // the line.
    let dir = std::env::temp_dir().join(format!("wavetrace-badmesh-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("empty.obj"), "# nothing here\n").unwrap();
    std::fs::write(dir.join("flat.obj"), "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n").unwrap();
    std::fs::write(dir.join("bad_index.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n").unwrap();
    let mesh = |file: &str| {
        let text = with_objects(&format!(r#"{{"type": "mesh", "file": "{file}", "material": "red"}}"#));
        load::from_str_in(&text, "bad.json", "bad", &dir).unwrap_err()
    };
    for (file, reason) in [
        ("missing.obj", "cannot read"),
        ("empty.obj", "no faces"),
        ("flat.obj", "zero area"),
        ("bad_index.obj", "line 4: face corner \"7\" refers to vertex 7"),
    ] {
        let e = mesh(file);
        assert_eq!((e.file.as_str(), e.path.as_str()), ("bad.json", "objects[5].file"), "{e}");
        assert!(e.reason.contains(reason) && e.reason.contains(file), "{file}: {e}");
    }
    std::fs::remove_dir_all(&dir).ok();
    // A generated terrain takes a triangle count in range, and nothing of a file mesh's.
    for (terrain, path, reason) in [
        ("0", "objects[5].terrain", "expected a triangle count in 1..=10000000, found a number (0)"),
        ("10000001", "objects[5].terrain", "found a number (10000001)"),
        ("\"100\"", "objects[5].terrain", "found a string"),
        ("2.5", "objects[5].terrain", "found a number (2.5)"),
    ] {
        let text = with_objects(&format!(r#"{{"type": "mesh", "terrain": {terrain}, "material": "red"}}"#));
        assert_error(&text, path, &[reason]);
    }
    assert_error(
        &with_objects(r#"{"type": "mesh", "terrain": 10, "file": "x.obj", "material": "red"}"#),
        "objects[5].file",
        &["unknown field"],
    );
}
