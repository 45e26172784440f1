//! `wavetrace scene list|export`.

use crate::scene::{builtin, export};

/// `wavetrace scene --help`.
pub const EXAMPLES: &str = "\
Examples:
  wavetrace scene list                                   # the built-in scenes
  wavetrace scene export three-spheres > my_scene.json   # a starting point to edit
  wavetrace render --scene my_scene.json --method wavefront --out mine.exr --png mine.png

The scene format (wavetrace-scene/1) is described in docs/cli-and-configs.md#scene-files;
experiments/scenes/my_scene.json is a small example.";

#[derive(clap::Subcommand, Debug)]
pub enum SceneCommand {
    /// List the built-in scenes.
    #[command(
        after_help = "Examples:\n  wavetrace scene list\n  wavetrace render --scene cornell --method megakernel --out cornell.exr\n\nspheres-N takes any N from 1 to 1000000 (e.g. spheres-100000) and rtiow-heavy-O any O from 1 to 16."
    )]
    List,
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
