//! `wavetrace scene list|info|export`.

use std::fmt::Write as _;

use crate::scene::{builtin, export, gltf, Background, Material, MeshSource, Scene, Texture};

/// `wavetrace scene --help`.
pub const EXAMPLES: &str = "\
Examples:
  wavetrace scene list                                   # the built-in scenes
  wavetrace scene export three-spheres > my_scene.json   # a starting point to edit
  wavetrace scene info my_scene.json                     # what a scene holds (glTF: what was mapped)
  wavetrace render --scene my_scene.json --method wavefront --out mine.exr --png mine.png

The scene format (wavetrace-scene/1) is described in docs/cli-and-configs.md#scene-files;
experiments/scenes/my_scene.json is a small example. glTF files (.gltf, .glb) are read too
(experiments/scenes/tetrahedra.gltf); docs/cli-and-configs.md#gltf-scenes tabulates the mapping.";

#[derive(clap::Subcommand, Debug)]
pub enum SceneCommand {
    /// List the built-in scenes.
    #[command(
        after_help = "Examples:\n  wavetrace scene list\n  wavetrace render --scene cornell --method megakernel --out cornell.exr\n\nspheres-N takes any N from 1 to 1000000 (e.g. spheres-100000) and rtiow-heavy-O any O from 1 to 16."
    )]
    List,
    /// Describe a scene: camera, materials, shapes; for glTF, what each object was mapped to and
    /// what could not be.
    #[command(
        after_help = "Examples:\n  wavetrace scene info cornell\n  wavetrace scene info experiments/scenes/my_scene.json\n  wavetrace scene info experiments/scenes/tetrahedra.gltf"
    )]
    Info {
        /// A built-in scene name, or a scene file (.json, .gltf, .glb).
        scene: String,
    },
    /// Print a built-in scene as JSON (loadable again with `--scene FILE`).
    #[command(
        after_help = "Example:\n  wavetrace scene export rtiow-final > final.json\n  wavetrace render --scene final.json --out final.exr"
    )]
    Export {
        /// Built-in scene name (see `wavetrace scene list`).
        name: String,
    },
}

pub fn run(cmd: SceneCommand) -> anyhow::Result<()> {
    match cmd {
        SceneCommand::List => {
            use std::io::Write;
            let mut out = std::io::stdout().lock();
            for (name, about) in builtin::list() {
                let primitives = builtin::by_name(name).map_or(0, |s| s.primitive_count());
                match writeln!(out, "{name:16} {primitives:6} primitives  {about}") {
                    // `wavetrace scene list | head`: the reader has all it wanted (println! would
                    // panic here).
                    Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => return Ok(()),
                    r => r?,
                }
            }
            Ok(())
        }
        SceneCommand::Info { scene } => {
            let path = std::path::Path::new(&scene);
            let text = if builtin::by_name(&scene).is_none() && path.exists() && gltf::is_gltf_path(path) {
                let import = gltf::read_unlogged(path)?;
                let mut text = info(&import.scene);
                let _ = writeln!(text, "mapped from glTF:");
                for line in &import.mapped {
                    let _ = writeln!(text, "  {line}");
                }
                let _ = writeln!(text, "not mapped ({} warnings):", import.warnings.len());
                for line in &import.warnings {
                    let _ = writeln!(text, "  {line}");
                }
                text
            } else {
                info(&Scene::resolve(&scene)?)
            };
            print!("{text}");
            Ok(())
        }
        SceneCommand::Export { name } => {
            let scene = builtin::by_name(&name).ok_or_else(|| match builtin::family_hint(&name) {
                Some(hint) => anyhow::anyhow!("{hint}"),
                None => {
                    let names: Vec<&str> = builtin::list().iter().map(|(n, _)| *n).collect();
                    anyhow::anyhow!("no built-in scene {name:?}; built-ins: {}", names.join(", "))
                }
            })?;
            println!("{}", export::to_json(&scene));
            Ok(())
        }
    }
}

/// `scene info`'s description of any scene.
pub fn info(scene: &Scene) -> String {
    let v = |v: glam::Vec3| format!("[{}, {}, {}]", v.x, v.y, v.z);
    let mut s = String::new();
    let c = &scene.camera;
    let _ = writeln!(s, "scene {:?}: {} primitives", scene.name, scene.primitive_count());
    let _ = writeln!(
        s,
        "camera: lookfrom {}, lookat {}, vup {}, vfov {}, defocus_angle {}, focus_dist {}",
        v(c.lookfrom),
        v(c.lookat),
        v(c.vup),
        c.vfov,
        c.defocus_angle,
        c.focus_dist
    );
    let _ = match scene.background {
        Background::Sky => writeln!(s, "background: sky"),
        Background::Constant(color) => writeln!(s, "background: constant {}", v(color)),
    };
    let _ = writeln!(s, "materials ({}):", scene.materials.len());
    for m in &scene.materials {
        let albedo = |t: &Texture| match t {
            Texture::Solid(color) => v(*color),
            Texture::Image { image, wrap, tint } => match scene.images.get(*image as usize) {
                Some(im) => format!(
                    "image {} ({}×{}, wrap {}/{}) × {}",
                    im.source,
                    im.width,
                    im.height,
                    wrap[0].name(),
                    wrap[1].name(),
                    v(*tint)
                ),
                None => format!("image #{image} (missing)"),
            },
            t => t.kind_name().to_owned(),
        };
        let what = match &m.material {
            Material::Lambertian { albedo: a } => format!("albedo {}", albedo(a)),
            Material::Metal { albedo: a, fuzz } => format!("albedo {}, fuzz {fuzz}", albedo(a)),
            Material::Dielectric { ior } => format!("ior {ior}"),
            Material::Emissive { radiance } => format!("radiance {}", v(*radiance)),
        };
        let _ = writeln!(s, "  {:?}: {}, {what}", m.name, m.material.kind_name());
    }
    let triangles: usize = scene.meshes.iter().map(|m| m.triangles.len()).sum();
    let _ = writeln!(
        s,
        "objects: {} spheres, {} quads, {} meshes ({triangles} triangles)",
        scene.spheres.len(),
        scene.quads.len(),
        scene.meshes.len()
    );
    for m in &scene.meshes {
        let source = match &m.source {
            MeshSource::File(f) => f.display().to_string(),
            MeshSource::Terrain(n) => format!("terrain {n}"),
            MeshSource::Gltf { primitive, .. } => primitive.clone(),
        };
        let material = scene.materials.get(m.material as usize).map_or("?", |m| m.name.as_str());
        let _ = writeln!(s, "  mesh {source}: {} triangles, material {material:?}", m.triangles.len());
    }
    s
}

#[cfg(test)]
mod tests {
    /// `scene list --help` states the families' ranges: they must be the code's.
    #[test]
    fn list_help_states_the_families_ranges() {
        use clap::CommandFactory;
        let mut cli = crate::cli::Cli::command();
        let list = cli.find_subcommand_mut("scene").unwrap().find_subcommand_mut("list").unwrap();
        let help = list.render_long_help().to_string();
        assert!(help.contains(&format!("1 to {}", crate::scene::builtin::SPHERES_MAX)), "{help}");
        assert!(help.contains(&format!("1 to {}", crate::scene::texture::MAX_OCTAVES)), "{help}");
    }
}
