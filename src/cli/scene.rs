//! `wavetrace scene list|export`.

use crate::scene::{builtin, export};

#[derive(clap::Subcommand, Debug)]
pub enum SceneCommand {
    /// List the built-in scenes.
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
