//! glTF 2.0 scenes (`scene::gltf`): written here by hand (JSON and a binary buffer, embedded,
//! external or as GLB), they must load as the equivalent JSON scene and render the same image on
//! every method; what cannot be mapped is warned about; malformed files name the field.

use std::path::{Path, PathBuf};
use std::process::Command;

use base64::Engine as _;
use glam::Vec3;
use serde_json::{json, Value};
use wavetrace::method::{render, Method, MethodOptions};
use wavetrace::scene::{gltf, load, InputError, Scene};
use wavetrace::settings::{Accel, RenderSettings};

use crate::common;

fn scratch(dir: &str) -> PathBuf {
    let dir = common::tmp().join("gltf").join(dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A primitive: positions, optional u16 indices, optional mode, material and TEXCOORD_0.
struct Prim {
    positions: Vec<[f32; 3]>,
    uvs: Option<Vec<[f32; 2]>>,
    indices: Option<Vec<u16>>,
    mode: Option<u32>,
    material: Option<usize>,
}

/// `root` (without buffers, bufferViews, accessors and meshes) completed with `meshes`, all data
/// in one buffer; returns the document (its buffer's `uri` unset) and the buffer's bytes.
fn document(mut root: Value, meshes: &[Vec<Prim>]) -> (Value, Vec<u8>) {
    let (mut bin, mut views, mut accessors) = (Vec::new(), Vec::new(), Vec::new());
    let mut gl_meshes = Vec::new();
    for mesh in meshes {
        let mut prims = Vec::new();
        for p in mesh {
            let offset = bin.len();
            for v in &p.positions {
                for c in v {
                    bin.extend_from_slice(&c.to_le_bytes());
                }
            }
            views.push(json!({"buffer": 0, "byteOffset": offset, "byteLength": bin.len() - offset}));
            let (lo, hi) = p.positions.iter().fold(([f32::MAX; 3], [f32::MIN; 3]), |(mut lo, mut hi), v| {
                for i in 0..3 {
                    lo[i] = lo[i].min(v[i]);
                    hi[i] = hi[i].max(v[i]);
                }
                (lo, hi)
            });
            accessors.push(json!({"bufferView": views.len() - 1, "componentType": 5126,
                "count": p.positions.len(), "type": "VEC3", "min": lo, "max": hi}));
            let mut prim = json!({"attributes": {"POSITION": accessors.len() - 1}});
            if let Some(uvs) = &p.uvs {
                let offset = bin.len();
                for c in uvs.iter().flatten() {
                    bin.extend_from_slice(&c.to_le_bytes());
                }
                views.push(json!({"buffer": 0, "byteOffset": offset, "byteLength": bin.len() - offset}));
                accessors.push(json!({"bufferView": views.len() - 1, "componentType": 5126,
                    "count": uvs.len(), "type": "VEC2"}));
                prim["attributes"]["TEXCOORD_0"] = json!(accessors.len() - 1);
            }
            if let Some(ind) = &p.indices {
                let offset = bin.len();
                for i in ind {
                    bin.extend_from_slice(&i.to_le_bytes());
                }
                views.push(json!({"buffer": 0, "byteOffset": offset, "byteLength": bin.len() - offset}));
                accessors.push(json!({"bufferView": views.len() - 1, "componentType": 5123,
                    "count": ind.len(), "type": "SCALAR"}));
                prim["indices"] = json!(accessors.len() - 1);
                while !bin.len().is_multiple_of(4) {
                    bin.push(0);
                }
            }
            if let Some(m) = p.mode {
                prim["mode"] = json!(m);
            }
            if let Some(m) = p.material {
                prim["material"] = json!(m);
            }
            prims.push(prim);
        }
        gl_meshes.push(json!({"primitives": prims}));
    }
    root["asset"] = json!({"version": "2.0"});
    root["buffers"] = json!([{"byteLength": bin.len()}]);
    root["bufferViews"] = json!(views);
    root["accessors"] = json!(accessors);
    root["meshes"] = json!(gl_meshes);
    (root, bin)
}

/// The document with its buffer as a base64 data URI, written to `path` (.gltf).
fn write_embedded(path: &Path, (root, bin): &(Value, Vec<u8>)) {
    let mut root = root.clone();
    let data = base64::engine::general_purpose::STANDARD.encode(bin);
    root["buffers"][0]["uri"] = json!(format!("data:application/octet-stream;base64,{data}"));
    std::fs::write(path, serde_json::to_string_pretty(&root).unwrap()).unwrap();
}

/// The document with its buffer in `bin_name` beside `path` (.gltf).
fn write_external(path: &Path, bin_name: &str, (root, bin): &(Value, Vec<u8>)) {
    let mut root = root.clone();
    root["buffers"][0]["uri"] = json!(bin_name.replace(' ', "%20"));
    std::fs::write(path.with_file_name(bin_name), bin).unwrap();
    std::fs::write(path, serde_json::to_string_pretty(&root).unwrap()).unwrap();
}

/// The document as a GLB: header, JSON chunk, BIN chunk (glTF 2.0 §4.4).
fn write_glb(path: &Path, (root, bin): &(Value, Vec<u8>)) {
    let mut text = serde_json::to_vec(root).unwrap();
    while !text.len().is_multiple_of(4) {
        text.push(b' ');
    }
    let mut bin = bin.clone();
    while !bin.len().is_multiple_of(4) {
        bin.push(0);
    }
    let total = 12 + 8 + text.len() + 8 + bin.len();
    let mut out = Vec::with_capacity(total);
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&(total as u32).to_le_bytes());
    out.extend_from_slice(&(text.len() as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(&text);
    out.extend_from_slice(&(bin.len() as u32).to_le_bytes());
    out.extend_from_slice(b"BIN\0");
    out.extend_from_slice(&bin);
    std::fs::write(path, out).unwrap();
}

fn tetrahedron() -> Vec<[f32; 3]> {
    let [a, b, c, d] = [[0.0, 0.0, 0.0], [0.5, 0.0, 0.0], [0.0, 0.5, 0.0], [0.0, 0.0, 0.5f32]];
    vec![a, c, b, a, b, d, a, d, c, b, c, d]
}

/// vfov as the importer computes it from a yfov of 40 degrees written in radians.
fn yfov() -> f32 {
    40f64.to_radians() as f32
}

/// Four materials (one of each kind), three meshes (indexed list, plain list under nested
/// transforms, strip) and a camera node. Coordinates are dyadic so that the transforms are exact.
fn test_document() -> (Value, Vec<u8>) {
    let root = json!({
        "extensionsUsed": ["KHR_materials_transmission", "KHR_materials_ior", "KHR_materials_emissive_strength"],
        "scene": 0,
        "scenes": [{"nodes": [0, 1, 3, 4]}],
        "nodes": [
            {"camera": 0, "translation": [0.0, 1.0, 6.0]},
            {"translation": [0.0, 0.5, 0.0], "scale": [2.0, 2.0, 2.0], "children": [2]},
            {"mesh": 1, "translation": [0.25, 0.0, -0.5]},
            {"mesh": 0},
            {"mesh": 2, "translation": [0.0, 3.0, 0.0]}
        ],
        "cameras": [{"type": "perspective", "perspective": {"yfov": yfov(), "znear": 0.01}}],
        "materials": [
            {"name": "red", "pbrMetallicRoughness": {"baseColorFactor": [0.75, 0.125, 0.125, 1.0], "metallicFactor": 0.0}},
            {"name": "steel", "pbrMetallicRoughness": {"baseColorFactor": [0.7, 0.6, 0.5, 1.0], "metallicFactor": 1.0, "roughnessFactor": 0.25}},
            {"name": "glass", "pbrMetallicRoughness": {"metallicFactor": 0.0, "roughnessFactor": 0.0},
             "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1.0}, "KHR_materials_ior": {"ior": 1.5}}},
            {"name": "lamp", "emissiveFactor": [1.0, 1.0, 1.0], "pbrMetallicRoughness": {"baseColorFactor": [0.0, 0.0, 0.0, 1.0]}, "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 4.0}}}
        ]
    });
    let floor = Prim {
        positions: vec![[-4.0, 0.0, -4.0], [4.0, 0.0, -4.0], [4.0, 0.0, 4.0], [-4.0, 0.0, 4.0]],
        uvs: None,
        indices: Some(vec![0, 2, 1, 0, 3, 2]),
        mode: None,
        material: Some(0),
    };
    let tetra = Prim { positions: tetrahedron(), uvs: None, indices: None, mode: None, material: Some(1) };
    // A strip of three triangles and a fan of two (a square).
    let glass = Prim {
        positions: vec![
            [-1.0, 0.0, 0.0],
            [-1.0, 0.5, 0.0],
            [-0.5, 0.0, 0.25],
            [-0.5, 0.5, 0.25],
            [0.0, 0.0, 0.0],
        ],
        uvs: None,
        indices: None,
        mode: Some(5),
        material: Some(2),
    };
    let lamp = Prim {
        positions: vec![[-1.0, 0.0, -1.0], [1.0, 0.0, -1.0], [1.0, 0.0, 1.0], [-1.0, 0.0, 1.0]],
        uvs: None,
        indices: None,
        mode: Some(6),
        material: Some(3),
    };
    document(root, &[vec![floor], vec![tetra, glass], vec![lamp]])
}

/// The same scene in our JSON format, its meshes as OBJ files (positions already transformed).
fn equivalent_json(dir: &Path) -> Scene {
    let obj = |name: &str, tris: &[[[f32; 3]; 3]]| {
        let mut text = String::new();
        for t in tris {
            for v in t {
                // `{}` prints an f32's shortest form that reads back exactly.
                text += &format!("v {} {} {}\n", v[0], v[1], v[2]);
            }
        }
        for i in 0..tris.len() {
            text += &format!("f {} {} {}\n", 3 * i + 1, 3 * i + 2, 3 * i + 3);
        }
        std::fs::write(dir.join(name), text).unwrap();
    };
    // The tetrahedron's and the strip's world transform: T(0, 0.5, 0) · S(2) · T(0.25, 0, -0.5).
    let world = |p: [f32; 3]| [2.0 * (p[0] + 0.25), 2.0 * p[1] + 0.5, 2.0 * (p[2] - 0.5)];
    let tet: Vec<[[f32; 3]; 3]> = tetrahedron().chunks(3).map(|t| [0, 1, 2].map(|k| world(t[k]))).collect();
    let f = [[-4.0, 0.0, -4.0], [4.0, 0.0, -4.0], [4.0, 0.0, 4.0], [-4.0, 0.0, 4.0]];
    obj("floor.obj", &[[f[0], f[2], f[1]], [f[0], f[3], f[2]]]);
    obj("steel.obj", &tet);
    // glTF 2.0 §3.7.2.1: strip triangle i is (i, i+1+i%2, i+2-i%2); fan triangle i is (i+1, i+2, 0).
    let g = [[-1.0, 0.0, 0.0], [-1.0, 0.5, 0.0], [-0.5, 0.0, 0.25], [-0.5, 0.5, 0.25], [0.0, 0.0, 0.0]]
        .map(world);
    obj("glass.obj", &[[g[0], g[1], g[2]], [g[1], g[3], g[2]], [g[2], g[3], g[4]]]);
    let l = [[-1.0, 3.0, -1.0], [1.0, 3.0, -1.0], [1.0, 3.0, 1.0], [-1.0, 3.0, 1.0]];
    obj("lamp.obj", &[[l[1], l[2], l[0]], [l[2], l[3], l[0]]]);
    let vfov = (f64::from(yfov())).to_degrees() as f32;
    let text = format!(
        r#"{{"format": "wavetrace-scene/1",
  "camera": {{"lookfrom": [0, 1, 6], "lookat": [0, 1, 5], "vup": [0, 1, 0], "vfov": {vfov}, "defocus_angle": 0, "focus_dist": 1}},
  "background": {{"type": "sky"}},
  "materials": {{
    "red": {{"type": "lambertian", "albedo": [0.75, 0.125, 0.125]}},
    "steel": {{"type": "metal", "albedo": [0.7, 0.6, 0.5], "fuzz": 0.25}},
    "glass": {{"type": "dielectric", "ior": 1.5}},
    "lamp": {{"type": "emissive", "radiance": [4, 4, 4]}}
  }},
  "objects": [
    {{"type": "mesh", "file": "steel.obj", "material": "steel"}},
    {{"type": "mesh", "file": "glass.obj", "material": "glass"}},
    {{"type": "mesh", "file": "floor.obj", "material": "red"}},
    {{"type": "mesh", "file": "lamp.obj", "material": "lamp"}}
  ]}}"#
    );
    std::fs::write(dir.join("scene.json"), text).unwrap();
    load::from_file(&dir.join("scene.json")).unwrap()
}

/// Everything but where the meshes came from.
#[track_caller]
fn assert_same_scene(a: &Scene, b: &Scene) {
    assert_eq!(a.camera, b.camera);
    assert_eq!(a.background, b.background);
    assert_eq!(a.materials, b.materials);
    assert_eq!((a.spheres.len(), a.quads.len()), (b.spheres.len(), b.quads.len()));
    let meshes = |s: &Scene| s.meshes.iter().map(|m| (m.triangles.clone(), m.material)).collect::<Vec<_>>();
    assert_eq!(meshes(a), meshes(b));
}

#[test]
fn gltf_loads_as_the_equivalent_json_scene_embedded_external_and_glb() {
    let dir = scratch("equivalent");
    let json_scene = equivalent_json(&dir);
    let doc = test_document();
    write_embedded(&dir.join("embedded.gltf"), &doc);
    write_external(&dir.join("external.gltf"), "external data.bin", &doc);
    write_glb(&dir.join("binary.GLB"), &doc);
    for name in ["embedded.gltf", "external.gltf", "binary.GLB"] {
        let path = dir.join(name);
        let import = gltf::read(&path).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_same_scene(&import.scene, &json_scene);
        assert!(import.warnings.is_empty(), "{name}: {:?}", import.warnings);
        // The one entry point for scene paths reads it too.
        assert_same_scene(&Scene::resolve(path.to_str().unwrap()).unwrap(), &json_scene);
        let mapped = import.mapped.join("\n");
        for want in [
            "materials[1] \"steel\" → metal, albedo [0.7, 0.6, 0.5], fuzz 0.25",
            "materials[2] \"glass\" → dielectric, ior 1.5",
            "materials[3] \"lamp\" → emissive, radiance [4, 4, 4]",
            "nodes[2] meshes[1].primitives[0] → 4 triangles, material \"steel\"",
            "nodes[0] cameras[0] → camera: lookfrom [0, 1, 6]",
        ] {
            assert!(mapped.contains(want), "{name}: mapping lacks {want:?}:\n{mapped}");
        }
    }
}

/// The acceptance test: a glTF scene renders the image its JSON equivalent does, bit for bit,
/// on every method (the same triangles, materials and camera make the same BVH and paths).
#[test]
fn gltf_renders_the_same_image_as_the_json_scene_on_every_method() {
    let dir = scratch("render");
    let json_scene = equivalent_json(&dir);
    write_glb(&dir.join("scene.glb"), &test_document());
    let gltf_scene = Scene::resolve(dir.join("scene.glb").to_str().unwrap()).unwrap();
    let gpu = common::gpu();
    for nee in [false, true] {
        let s = RenderSettings {
            width: 20,
            height: 14,
            spp: 4,
            max_depth: 8,
            seed: 5,
            accel: Accel::Bvh,
            nee,
            roulette: false,
        };
        for method in [Method::Cpu, Method::CpuF64, Method::Megakernel, Method::Wavefront] {
            if method.needs_gpu() && gpu.is_none() {
                continue; // common::gpu() has already failed the test where a GPU is required.
            }
            let run = |scene: &Scene| {
                render(method, scene, &s, &MethodOptions::default(), gpu, &|_| {}).unwrap().film
            };
            let (a, b) = (run(&json_scene), run(&gltf_scene));
            assert!(
                a.pixels.iter().any(|p| p.sum.iter().any(|&x| x > 0.0)),
                "{method:?}: a black image proves little"
            );
            assert!(
                a == b,
                "{} nee={nee}: the glTF scene's film differs from the JSON scene's",
                method.name()
            );
        }
    }
}

/// The glTF in `test_document` with `edit` applied, written embedded; the import's result.
fn import_edited(name: &str, edit: impl FnOnce(&mut Value)) -> Result<gltf::Import, InputError> {
    let (mut root, bin) = test_document();
    let dir = scratch("edited");
    let data = base64::engine::general_purpose::STANDARD.encode(&bin);
    root["buffers"][0]["uri"] = json!(format!("data:application/octet-stream;base64,{data}"));
    edit(&mut root);
    let path = dir.join(format!("{name}.gltf"));
    std::fs::write(&path, serde_json::to_string(&root).unwrap()).unwrap();
    gltf::read(&path)
}

/// A change to the test document.
type Edit = Box<dyn FnOnce(&mut Value)>;

#[test]
fn malformed_gltf_names_the_file_the_field_and_the_reason() {
    let cases: Vec<(&str, Edit, &str, &str)> = vec![
        (
            "missing-bin",
            Box::new(|r| r["buffers"][0]["uri"] = json!("nowhere.bin")),
            "buffers[0].uri",
            "cannot read",
        ),
        (
            "bad-base64",
            Box::new(|r| r["buffers"][0]["uri"] = json!("data:application/octet-stream;base64,@@@")),
            "buffers[0].uri",
            "base64",
        ),
        (
            "short-buffer",
            Box::new(|r| r["buffers"][0]["byteLength"] = json!(100000)),
            "buffers[0].byteLength",
            "has only",
        ),
        (
            "index-range",
            Box::new(|r| r["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = json!(99)),
            "meshes[0].primitives[0].attributes.POSITION",
            "Index out of range",
        ),
        (
            "no-min",
            Box::new(|r| r["accessors"][0].as_object_mut().unwrap().remove("min").map(|_| ()).unwrap()),
            "meshes[0].primitives[0].attributes.POSITION.min",
            "Missing",
        ),
        (
            "past-view",
            Box::new(|r| r["accessors"][0]["count"] = json!(40)),
            "meshes[0].primitives[0].attributes.POSITION",
            "reads past the end of bufferViews[0]",
        ),
        (
            "wrong-type",
            Box::new(|r| r["accessors"][0]["type"] = json!("VEC2")),
            "meshes[0].primitives[0].attributes.POSITION",
            "expected Vec3",
        ),
        (
            "vertex-index",
            Box::new(|r| {
                // The floor's index buffer (bufferViews[1]) holds u16 0, 2, 1, 0, 3, 2: point the
                // accessor at a view of the positions instead, whose bytes are large indices.
                r["accessors"][1]["bufferView"] = json!(0);
                r["accessors"][1]["count"] = json!(6);
            }),
            "meshes[0].primitives[0].indices",
            "but POSITION has 4 vertices",
        ),
        (
            "yfov",
            Box::new(|r| r["cameras"][0]["perspective"]["yfov"] = json!(4.0)),
            "cameras[0].perspective.yfov",
            "(0, π)",
        ),
        (
            "roughness",
            Box::new(|r| r["materials"][1]["pbrMetallicRoughness"]["roughnessFactor"] = json!(2.0)),
            "materials[1].pbrMetallicRoughness.roughnessFactor",
            "[0, 1]",
        ),
        ("cycle", Box::new(|r| r["nodes"][2]["children"] = json!([1])), "nodes[1]", "reached twice"),
        (
            "points-only",
            Box::new(|r| {
                for m in r["meshes"].as_array_mut().unwrap() {
                    for p in m["primitives"].as_array_mut().unwrap() {
                        p["mode"] = json!(0);
                    }
                }
            }),
            "scenes[0]",
            "reaches no triangles",
        ),
    ];
    for (name, edit, path, reason) in cases {
        let e = import_edited(name, edit).err().unwrap_or_else(|| panic!("{name}: loaded"));
        assert!(e.file.ends_with(&format!("{name}.gltf")), "{name}: {e}");
        assert_eq!(e.path, path, "{name}: {e}");
        assert!(e.reason.contains(reason), "{name}: {e}");
    }
    let dir = scratch("malformed");
    let text = dir.join("text.gltf");
    std::fs::write(&text, "{\"asset\": {\"version\": \"2.0\"},").unwrap();
    let e = gltf::read(&text).unwrap_err();
    assert!(e.reason.contains("not valid glTF JSON") && e.reason.contains("line 1"), "{e}");
    let glb = dir.join("truncated.glb");
    std::fs::write(&glb, b"glTF\x02\0\0\0\xff\0\0\0").unwrap();
    let e = gltf::read(&glb).unwrap_err();
    assert!(e.reason.contains("GLB"), "{e}");
}

#[test]
fn what_cannot_be_mapped_is_named_in_a_warning() {
    let dir = scratch("warnings");
    // A 2×1 PNG, black and white: its mean linear colour is 0.5.
    let png = dir.join("half.png");
    wavetrace::image_io::write_png_rgb8(&png, 2, 1, &[0, 0, 0, 255, 255, 255]).unwrap();
    // JPEG signature bytes: this build decodes PNG only.
    std::fs::write(scratch("edited").join("photo.jpg"), b"\xff\xd8\xff\xe0\0\x10JFIF\0").unwrap();
    let import = import_edited("warnings", |r| {
        r["extensionsUsed"].as_array_mut().unwrap().push(json!("KHR_lights_punctual"));
        r["images"] = json!([{"uri": "../warnings/half.png"}, {"uri": "photo.jpg"}]);
        r["textures"] = json!([{"source": 0}, {"source": 1}]);
        let red = &mut r["materials"][0];
        red["pbrMetallicRoughness"]["baseColorTexture"] = json!({"index": 0});
        red["normalTexture"] = json!({"index": 0});
        red["alphaMode"] = json!("BLEND");
        r["materials"][1]["pbrMetallicRoughness"]["metallicFactor"] = json!(0.7);
        r["materials"][1]["pbrMetallicRoughness"]["baseColorTexture"] = json!({"index": 1});
        r["materials"][1]["extensions"] = json!({"KHR_materials_clearcoat": {"clearcoatFactor": 1.0}});
        // The lamp primitive loses its material: glTF's default applies.
        r["meshes"][2]["primitives"][0].as_object_mut().unwrap().remove("material");
        r["meshes"][0]["primitives"]
            .as_array_mut()
            .unwrap()
            .push(json!({"attributes": {"POSITION": 0}, "mode": 1}));
        r["materials"][3].as_object_mut().unwrap().remove("pbrMetallicRoughness");
        r["nodes"][0]["camera"] = json!(1);
        r["cameras"].as_array_mut().unwrap().push(json!({"type": "orthographic",
            "orthographic": {"xmag": 1.0, "ymag": 1.0, "znear": 0.1, "zfar": 10.0}}));
    })
    .unwrap();
    let w = import.warnings.join("\n");
    for want in [
        "extensionsUsed: KHR_lights_punctual is not mapped",
        "meshes[0].primitives[0].attributes.TEXCOORD_0: missing, but the material has a baseColorTexture",
        "materials[0].normalTexture: ignored",
        "materials[0]: alpha ignored",
        "materials[1].pbrMetallicRoughness.baseColorTexture: ignored (images[1]",
        "materials[1].pbrMetallicRoughness.metallicFactor: 0.7 is not blended",
        "materials[1].extensions.KHR_materials_clearcoat: not mapped",
        "meshes[2].primitives[0].material: none, so glTF's default material",
        "meshes[0].primitives[1].mode: Lines has no surface to render; skipped",
        "cameras[1] is orthographic",
        "materials[3]: emissive, so it only emits: its reflection (base colour [1, 1, 1]",
        "cameras: no perspective camera in the scene; using one that frames its bounds",
    ] {
        assert!(w.contains(want), "warnings lack {want:?}:\n{w}");
    }
    let scene = &import.scene;
    let red = &scene.materials[0].material;
    let want = wavetrace::scene::Texture::Image {
        image: 0,
        wrap: [wavetrace::scene::Wrap::Repeat; 2],
        tint: Vec3::new(0.75, 0.125, 0.125),
    };
    assert_eq!(red, &wavetrace::scene::Material::Lambertian { albedo: want });
    assert_eq!(
        (scene.images.len(), scene.images[0].width, scene.images[0].height),
        (1, 2, 1),
        "the JPEG is not kept"
    );
    assert_eq!(scene.images[0].mean(), Vec3::splat(0.5));
    let last = scene.materials.last().unwrap();
    assert_eq!(last.name, "gltf-default");
    assert_eq!(last.material, wavetrace::scene::Material::Metal { albedo: Vec3::ONE.into(), fuzz: 1.0 });
    assert_eq!(scene.meshes.last().unwrap().material as usize, scene.materials.len() - 1);
    // The framing camera looks at the bounds' centre down −Z.
    assert_eq!(scene.camera.vup, Vec3::Y);
    assert!(scene.camera.lookfrom.z > scene.camera.lookat.z);
}

#[test]
fn cli_renders_a_gltf_scene_and_scene_info_shows_the_mapping() {
    let dir = scratch("cli");
    let glb = dir.join("model.glb");
    write_glb(&glb, &test_document());
    let exr = dir.join("model.exr");
    let wavetrace = |args: &[&str]| Command::new(common::bin()).args(args).output().unwrap();
    let out = wavetrace(&[
        "render",
        "--scene",
        glb.to_str().unwrap(),
        "--method",
        "cpu",
        "--width",
        "8",
        "--height",
        "6",
        "--spp",
        "2",
        "--out",
        exr.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(exr.exists());

    let out = wavetrace(&["scene", "info", glb.to_str().unwrap()]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    for want in [
        "scene \"model\": 11 primitives",
        "\"glass\": dielectric, ior 1.5",
        "mapped from glTF:",
        "background → sky",
        "not mapped (0 warnings):",
    ] {
        assert!(text.contains(want), "scene info lacks {want:?}:\n{text}");
    }

    let bad = dir.join("bad.gltf");
    std::fs::write(&bad, "{\"asset\": {\"version\": \"2.0\"}, \"scenes\": [{\"nodes\": [7]}]}").unwrap();
    let out = wavetrace(&["scene", "info", bad.to_str().unwrap()]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && !err.contains("panicked"), "{err}");
    assert!(err.contains("bad.gltf") && err.contains("scenes[0].nodes[0]"), "{err}");
}

/// A 4×3 PNG whose texels all differ, so that a lookup in the wrong place shows.
fn texture_png(path: &Path) {
    let rgb: Vec<u8> = (0..12u32)
        .flat_map(|i| [(20 * i + 15) as u8, (230 - 17 * i) as u8, (60 + 90 * (i % 3)) as u8])
        .collect();
    wavetrace::image_io::write_png_rgb8(path, 4, 3, &rgb).unwrap();
}

/// A textured wall facing the camera (lambertian, texture mirrored along u, clamped along v) and
/// a textured metal floor (repeated), their coordinates running past [0, 1] so that every wrap
/// mode is seen, under the sky. Coordinates are dyadic, so the OBJ twin's flipped v is exact.
fn textured_document(png_uri: &str) -> (Value, Vec<u8>) {
    let root = json!({
        "scene": 0,
        "scenes": [{"nodes": [0, 1]}],
        "nodes": [{"camera": 0, "translation": [0.0, 0.0, 4.0]}, {"mesh": 0}],
        "cameras": [{"type": "perspective", "perspective": {"yfov": yfov(), "znear": 0.01}}],
        "images": [{"uri": png_uri}],
        "samplers": [{"wrapS": 33648, "wrapT": 33071}, {}],
        "textures": [{"source": 0, "sampler": 0}, {"source": 0, "sampler": 1}],
        "materials": [
            {"name": "wall", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "metallicFactor": 0.0}},
            {"name": "floor", "pbrMetallicRoughness": {"baseColorFactor": [0.75, 0.75, 0.5, 1.0],
                "baseColorTexture": {"index": 1}, "metallicFactor": 1.0, "roughnessFactor": 0.25}}
        ]
    });
    let wall = Prim {
        positions: vec![[-2.0, -1.5, 0.0], [2.0, -1.5, 0.0], [2.0, 1.5, 0.0], [-2.0, 1.5, 0.0]],
        uvs: Some(vec![[-0.5, 1.25], [1.5, 1.25], [1.5, -0.25], [-0.5, -0.25]]),
        indices: Some(vec![0, 1, 2, 0, 2, 3]),
        mode: None,
        material: Some(0),
    };
    let floor = Prim {
        positions: vec![[-2.0, -1.5, 0.0], [-2.0, -1.5, 4.0], [2.0, -1.5, 4.0], [2.0, -1.5, 0.0]],
        uvs: Some(vec![[0.0, 0.0], [0.0, 3.5], [2.25, 3.5], [2.25, 0.0]]),
        indices: Some(vec![0, 1, 2, 0, 2, 3]),
        mode: None,
        material: Some(1),
    };
    document(root, &[vec![wall, floor]])
}

/// The textured glTF as our JSON format: OBJ meshes with `vt` (v flipped, OBJ's v runs up) and
/// image albedos naming the same PNG.
fn textured_json(dir: &Path, png: &str) -> Scene {
    let obj = |name: &str, p: [[f32; 3]; 4], uv: [[f32; 2]; 4]| {
        let mut text = String::new();
        for v in p {
            text += &format!("v {} {} {}\n", v[0], v[1], v[2]);
        }
        for t in uv {
            text += &format!("vt {} {}\n", t[0], 1.0 - t[1]);
        }
        text += "f 1/1 2/2 3/3\nf 1/1 3/3 4/4\n";
        std::fs::write(dir.join(name), text).unwrap();
    };
    obj(
        "wall.obj",
        [[-2.0, -1.5, 0.0], [2.0, -1.5, 0.0], [2.0, 1.5, 0.0], [-2.0, 1.5, 0.0]],
        [[-0.5, 1.25], [1.5, 1.25], [1.5, -0.25], [-0.5, -0.25]],
    );
    obj(
        "floor.obj",
        [[-2.0, -1.5, 0.0], [-2.0, -1.5, 4.0], [2.0, -1.5, 4.0], [2.0, -1.5, 0.0]],
        [[0.0, 0.0], [0.0, 3.5], [2.25, 3.5], [2.25, 0.0]],
    );
    let vfov = (f64::from(yfov())).to_degrees() as f32;
    let text = format!(
        r#"{{"format": "wavetrace-scene/1",
  "camera": {{"lookfrom": [0, 0, 4], "lookat": [0, 0, 3], "vup": [0, 1, 0], "vfov": {vfov}, "defocus_angle": 0, "focus_dist": 1}},
  "background": {{"type": "sky"}},
  "materials": {{
    "wall": {{"type": "lambertian", "albedo": {{"type": "image", "file": "{png}", "wrap": ["mirror", "clamp"], "tint": [1, 1, 1]}}}},
    "floor": {{"type": "metal", "albedo": {{"type": "image", "file": "{png}", "wrap": ["repeat", "repeat"], "tint": [0.75, 0.75, 0.5]}}, "fuzz": 0.25}}
  }},
  "objects": [
    {{"type": "mesh", "file": "wall.obj", "material": "wall"}},
    {{"type": "mesh", "file": "floor.obj", "material": "floor"}}
  ]}}"#
    );
    std::fs::write(dir.join("textured.json"), text).unwrap();
    load::from_file(&dir.join("textured.json")).unwrap()
}

fn textured_settings(spp: u32) -> RenderSettings {
    RenderSettings {
        width: 32,
        height: 24,
        spp,
        max_depth: 4,
        seed: 9,
        accel: Accel::Bvh,
        nee: false,
        roulette: false,
    }
}

/// Image textures: the glTF loads as its JSON twin (same images, wraps, coordinates), renders
/// the same film bit for bit on every method, and `scene info` shows the mapping.
#[test]
fn textured_gltf_renders_the_same_image_as_its_json_twin_on_every_method() {
    let dir = scratch("textured");
    texture_png(&dir.join("tex.png"));
    let json_scene = textured_json(&dir, "tex.png");
    let glb = dir.join("textured.glb");
    write_glb(&glb, &textured_document("tex.png"));
    let import = gltf::read(&glb).unwrap();
    assert!(import.warnings.is_empty(), "{:?}", import.warnings);
    let gltf_scene = import.scene;
    assert_same_scene(&gltf_scene, &json_scene);
    assert_eq!(gltf_scene.images, json_scene.images);
    assert_eq!(json_scene.images.len(), 1, "one PNG, read once for both materials");
    let uvs = |s: &Scene| s.meshes.iter().map(|m| m.uvs.clone()).collect::<Vec<_>>();
    assert_eq!(uvs(&gltf_scene), uvs(&json_scene));
    let mapped = import.mapped.join("\n");
    assert!(mapped.contains("images[0] → image 4×3"), "{mapped}");
    assert!(mapped.contains("wrap mirror/clamp"), "{mapped}");

    // Only scenes with image textures carry coordinates and texels, and compile the lookup in.
    let packed = wavetrace::packed_scene::PackedScene::new(&json_scene, Accel::Bvh);
    assert_eq!(packed.texture_kinds(), 1 << wavetrace::layout::texture_kind::IMAGE);
    assert_eq!(packed.uvs.len(), packed.primitives.len());
    assert_eq!(packed.texels.len(), 256 + 4 + 12, "table, one header, 4×3 texels");
    // Images too big for the adapter's storage binding are refused naming their files.
    let texel_bytes = 4 * packed.texels.len() as u64;
    let err =
        wavetrace::gpu::scene_buffers::check_fits_limits(&packed, "Tiny GPU", texel_bytes - 1, u64::MAX)
            .unwrap_err()
            .to_string();
    assert!(err.contains("image textures do not fit on Tiny GPU") && err.contains("tex.png (48 B)"), "{err}");
    let plain =
        wavetrace::packed_scene::PackedScene::new(&equivalent_json(&scratch("textured-plain")), Accel::Bvh);
    assert!(plain.uvs.is_empty() && plain.texels.is_empty());
    let gpu = common::gpu();
    let s = textured_settings(4);
    for method in [Method::Cpu, Method::CpuF64, Method::Megakernel, Method::Wavefront] {
        if method.needs_gpu() && gpu.is_none() {
            continue;
        }
        let run =
            |scene: &Scene| render(method, scene, &s, &MethodOptions::default(), gpu, &|_| {}).unwrap().film;
        let (a, b) = (run(&json_scene), run(&gltf_scene));
        assert!(a.pixels.iter().any(|p| p.sum.iter().any(|&x| x > 0.0)), "{method:?}: black");
        assert!(a == b, "{}: the textured glTF's film differs from the JSON twin's", method.name());
    }

    let out = Command::new(common::bin()).args(["scene", "info", glb.to_str().unwrap()]).output().unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(text.contains("images[0] (4×3, wrap mirror/clamp) × [1, 1, 1]"), "{text}");
    // A JSON scene written back out loads as itself, image and all.
    let again =
        load::from_str_in(&wavetrace::scene::export::to_json(&json_scene), "<export>", "textured", &dir)
            .unwrap();
    assert_eq!(again, json_scene);
}

/// The GPU methods' lookup agrees with the CPU reference's, pixel by pixel within noise, and the
/// texture shows: the same scene with each image replaced by its mean colour renders otherwise.
#[test]
fn textured_scene_agrees_between_cpu_and_gpu() {
    let dir = scratch("textured-agree");
    texture_png(&dir.join("tex.png"));
    let scene = textured_json(&dir, "tex.png");
    let s = textured_settings(48);
    let run = |method, scene: &Scene| {
        render(method, scene, &s, &MethodOptions::default(), common::gpu(), &|_| {}).unwrap().film
    };
    let cpu = run(Method::Cpu, &scene);
    common::assert_agree_rays("textured f32 vs f64", &cpu, &run(Method::CpuF64, &scene), 1e-2);
    let mut flat = scene.clone();
    for m in &mut flat.materials {
        if let wavetrace::scene::Material::Lambertian { albedo }
        | wavetrace::scene::Material::Metal { albedo, .. } = &mut m.material
        {
            if let wavetrace::scene::Texture::Image { image, tint, .. } = *albedo {
                *albedo = wavetrace::scene::Texture::Solid(tint * scene.images[image as usize].mean());
            }
        }
    }
    let t = wavetrace::stats::z_test(&cpu, &run(Method::Cpu, &flat), 0.01);
    assert!(t.pass_fraction < 0.9, "the texture barely changes the image: {t:?}");
    if common::gpu().is_none() {
        return;
    }
    for method in [Method::Megakernel, Method::Wavefront] {
        common::assert_agree_rays(
            &format!("textured cpu vs {}", method.name()),
            &cpu,
            &run(method, &scene),
            common::F32_RAY_TOLERANCE,
        );
    }
}

#[test]
fn malformed_textures_name_the_file_the_field_and_the_reason() {
    let dir = scratch("textured-bad");
    texture_png(&dir.join("tex.png"));
    std::fs::write(dir.join("fake.png"), b"GIF89a not a png").unwrap();
    type TexEdit = Box<dyn FnOnce(&mut Value, &mut Vec<u8>)>;
    let cases: Vec<(&str, TexEdit, &str, &str)> = vec![
        (
            "missing",
            Box::new(|r, _| r["images"][0]["uri"] = json!("nowhere.png")),
            "images[0].uri",
            "cannot read",
        ),
        ("not-png", Box::new(|r, _| r["images"][0]["uri"] = json!("fake.png")), "images[0].uri", "not a PNG"),
        (
            "source-range",
            Box::new(|r, _| r["textures"][0]["source"] = json!(7)),
            "textures[0].source",
            "Index out of bounds",
        ),
        (
            "texture-range",
            Box::new(|r, _| {
                r["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["index"] = json!(5)
            }),
            "materials[0].pbrMetallicRoughness.baseColorTexture.index",
            "Index out of bounds",
        ),
        (
            "uv-type",
            Box::new(|r, _| r["accessors"][1]["type"] = json!("VEC3")),
            "meshes[0].primitives[0].attributes.TEXCOORD_0",
            "expected Vec2",
        ),
        (
            "uv-count",
            Box::new(|r, _| r["accessors"][1]["count"] = json!(3)),
            "meshes[0].primitives[0].attributes.TEXCOORD_0",
            "has 3 elements, but POSITION has 4 vertices",
        ),
        (
            "uv-integer",
            Box::new(|r, _| r["accessors"][1]["componentType"] = json!(5121)),
            "meshes[0].primitives[0].attributes.TEXCOORD_0",
            "(integers normalized)",
        ),
    ];
    for (name, edit, path, reason) in cases {
        let (mut root, mut bin) = textured_document("tex.png");
        edit(&mut root, &mut bin);
        let file = dir.join(format!("{name}.gltf"));
        write_external(&file, &format!("{name}.bin"), &(root, bin));
        let e = gltf::read(&file).err().unwrap_or_else(|| panic!("{name}: loaded"));
        assert!(e.file.ends_with(&format!("{name}.gltf")), "{name}: {e}");
        assert_eq!(e.path, path, "{name}: {e}");
        assert!(e.reason.contains(reason), "{name}: {e}");
    }
    // The JSON format's image albedo: a bad file or wrap names the scene file and the field.
    for (albedo, path, reason) in [
        (
            r#"{"type": "image", "file": "nowhere.png", "wrap": ["repeat", "repeat"], "tint": [1, 1, 1]}"#,
            "materials.m.albedo.file",
            "cannot read",
        ),
        (
            r#"{"type": "image", "file": "fake.png", "wrap": ["repeat", "repeat"], "tint": [1, 1, 1]}"#,
            "materials.m.albedo.file",
            "fake.png: not a PNG",
        ),
        (
            r#"{"type": "image", "file": "tex.png", "wrap": ["repeat", "wrap"], "tint": [1, 1, 1]}"#,
            "materials.m.albedo.wrap[1]",
            "unknown wrap \"wrap\"",
        ),
        (
            r#"{"type": "image", "file": "tex.png", "wrap": "repeat", "tint": [1, 1, 1]}"#,
            "materials.m.albedo.wrap",
            "expected [u, v] wraps",
        ),
        (
            r#"{"type": "image", "file": "tex.png", "wrap": ["repeat", "clamp"], "tint": [1, -1, 1]}"#,
            "materials.m.albedo.tint[1]",
            "must be >= 0",
        ),
    ] {
        let text = format!(
            r#"{{"format": "wavetrace-scene/1",
  "camera": {{"lookfrom": [0, 0, 4], "lookat": [0, 0, 0], "vup": [0, 1, 0], "vfov": 40, "defocus_angle": 0, "focus_dist": 1}},
  "background": {{"type": "sky"}},
  "materials": {{"m": {{"type": "lambertian", "albedo": {albedo}}}}},
  "objects": [{{"type": "quad", "corner": [0, 0, 0], "u": [1, 0, 0], "v": [0, 1, 0], "material": "m"}}]}}"#
        );
        let e = load::from_str_in(&text, "bad.json", "bad", &dir).unwrap_err();
        assert_eq!((e.file.as_str(), e.path.as_str()), ("bad.json", path), "{e}");
        assert!(e.reason.contains(reason), "{e}");
    }
}

/// The WGSL lookup (`shaders/shared/image_texture.wgsl`) agrees with the CPU reference's
/// (`cpu/image_texture.rs`) at coordinates inside, on and beyond the image, in every wrap mode:
/// to a few ulps (the GPU may fuse the coordinate's multiply and add, which can move a texel
/// boundary by an ulp, so equality is not asked).
#[test]
fn wgsl_image_lookup_matches_the_cpu() {
    use wavetrace::gpu::buffers::{read_back, storage_entry, storage_init, storage_zeroed};
    use wavetrace::layout::{image_word, texture_kind, MaterialRecord};
    let Some(ctx) = common::gpu() else { return };
    let dir = scratch("image-probe");
    texture_png(&dir.join("tex.png"));
    let mut scene = textured_json(&dir, "tex.png");
    // A second, 1×1 image: the header of an image other than the first.
    let one = wavetrace::scene::Image {
        width: 1,
        height: 1,
        texels: vec![0x00_80_40_20],
        ..scene.images[0].clone()
    };
    scene.images.push(one);
    let packed = wavetrace::packed_scene::PackedScene::new(&scene, Accel::Bvh);
    let mut rng = wavetrace::rng::Stream::new(17);
    let mut probes: Vec<[f32; 4]> = Vec::new();
    for image in 0..2u32 {
        for wrap in 0..9u32 {
            let word =
                image | (wrap % 3) << image_word::WRAP_U_SHIFT | (wrap / 3) << image_word::WRAP_V_SHIFT;
            for k in 0..64 {
                // Texel centres and edges, then anywhere in [-3, 3).
                let uv = if k < 16 {
                    [(k % 4) as f32 / 8.0, (k / 4) as f32 / 6.0]
                } else {
                    [rng.range(-3.0, 3.0), rng.range(-3.0, 3.0)]
                };
                probes.push([uv[0], uv[1], f32::from_bits(word), 0.0]);
            }
        }
    }
    let n = probes.len() as u64;
    let none = wgpu::BufferUsages::empty();
    let texels = storage_init(ctx, "texels", &packed.texels, none).unwrap();
    let input = storage_init(ctx, "probe in", &probes, none).unwrap();
    let output = storage_zeroed(ctx, "probe out", n * 16, wgpu::BufferUsages::COPY_SRC).unwrap();
    let scene_layout = ctx.device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: None,
        entries: &[storage_entry(7, true)],
    });
    let io_layout = ctx.device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: None,
        entries: &[storage_entry(0, true), storage_entry(1, false)],
    });
    let scene_group = ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: None,
        layout: &scene_layout,
        entries: &[wgpu::BindGroupEntry { binding: 7, resource: texels.as_entire_binding() }],
    });
    let io_group = ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: None,
        layout: &io_layout,
        entries: &[
            wgpu::BindGroupEntry { binding: 0, resource: input.as_entire_binding() },
            wgpu::BindGroupEntry { binding: 1, resource: output.as_entire_binding() },
        ],
    });
    let module = ctx.shader("image_probe", wavetrace::gpu::shaders::IMAGE_PROBE, Default::default()).unwrap();
    let pipeline = ctx.compute_pipeline("image_probe", &module, &[&scene_layout, &io_layout], &[]).unwrap();
    let mut enc = ctx.device.create_command_encoder(&Default::default());
    {
        let mut pass = enc.begin_compute_pass(&Default::default());
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &scene_group, &[]);
        pass.set_bind_group(1, &io_group, &[]);
        pass.dispatch_workgroups((n as u32).div_ceil(64), 1, 1);
    }
    ctx.queue.submit([enc.finish()]);
    let gpu: Vec<[f32; 4]> = read_back(ctx, &output, n * 16).unwrap();
    for (q, g) in probes.iter().zip(&gpu) {
        let m = MaterialRecord {
            color: [1.0; 3],
            texture: texture_kind::IMAGE,
            octaves: q[2].to_bits(),
            ..Default::default()
        };
        let want = wavetrace::cpu::image_texture::image_albedo(&m, &packed.texels, [q[0], q[1]]);
        for (c, (w, got)) in [want.x, want.y, want.z].iter().zip(g).enumerate() {
            assert!(
                (w - got).abs() <= 1e-5,
                "uv ({}, {}) word {:#x} channel {c}: CPU {w}, GPU {got}",
                q[0],
                q[1],
                q[2].to_bits()
            );
        }
    }
}

/// An asset that is not glTF 2.x (1.0 is another format) is refused, naming `asset.version`;
/// and `scene info` shows each warning once (on stdout, not logged to stderr as well).
#[test]
fn gltf_other_than_2_is_refused_and_warnings_show_once() {
    let Err(err) = import_edited("version-1", |root| root["asset"]["version"] = json!("1.0")) else {
        panic!("a glTF 1.0 asset was accepted")
    };
    let text = err.to_string();
    assert!(text.contains("asset.version") && text.contains("only glTF 2.x"), "{text}");
    assert!(import_edited("version-2-1", |root| root["asset"]["version"] = json!("2.1")).is_ok());

    let dir = scratch("warn-once");
    let (mut root, bin) = test_document();
    root["extensionsUsed"].as_array_mut().unwrap().push(json!("EXT_not_mapped_anywhere"));
    let path = dir.join("warned.gltf");
    write_embedded(&path, &(root, bin));
    let out = Command::new(common::bin()).args(["scene", "info"]).arg(&path).output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let all = format!("{}{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
    assert_eq!(all.matches("EXT_not_mapped_anywhere is not mapped").count(), 1, "{all}");
}
