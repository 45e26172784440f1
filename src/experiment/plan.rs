//! An experiment's runs: every combination of scene × resolution × max depth × NEE × spp × method
//! variant, numbered in that order (methods innermost), and the share of them one shard runs.

use std::fmt;
use std::str::FromStr;

use super::config::ExperimentConfig;
use crate::settings::RenderSettings;

/// One run to do: which scene, settings and method variant.
#[derive(Clone, Debug, PartialEq)]
pub struct RunSpec {
    /// Position in the whole config's plan (the same in every shard).
    pub index: usize,
    /// Unique, file-name safe: `007-rtiow-final-400x225-16spp-d50-wavefront` (`-d50-nee-` with
    /// next-event estimation, `-rr-` with roulette).
    pub id: String,
    /// Index into `config.scenes`.
    pub scene: usize,
    pub settings: RenderSettings,
    /// Index into `config.methods`.
    pub variant: usize,
}

/// Every run of the config, in plan order.
pub fn plan(config: &ExperimentConfig) -> Vec<RunSpec> {
    let mut runs = Vec::new();
    for (scene, entry) in config.scenes.iter().enumerate() {
        for settings in config.settings() {
            for (variant, v) in config.methods.iter().enumerate() {
                let index = runs.len();
                let id = format!(
                    "{index:03}-{}-{}x{}-{}spp-d{}{}{}-{}",
                    file_safe(&entry.scene.name),
                    settings.width,
                    settings.height,
                    settings.spp,
                    settings.max_depth,
                    if settings.nee { "-nee" } else { "" },
                    if settings.roulette { "-rr" } else { "" },
                    file_safe(&v.label)
                );
                runs.push(RunSpec { index, id, scene, settings: settings.clone(), variant });
            }
        }
    }
    runs
}

/// `text` with every character outside `[A-Za-z0-9._-]` replaced by `-`.
pub fn file_safe(text: &str) -> String {
    text.chars().map(|c| if c.is_ascii_alphanumeric() || "._-".contains(c) { c } else { '-' }).collect()
}

/// `--shard I/N`: this process runs the runs whose index is I modulo N (I counts from 0, so a
/// Slurm array `--array=0-(N-1)` passes `$SLURM_ARRAY_TASK_ID/N`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Shard {
    pub index: u32,
    pub count: u32,
}

impl Shard {
    pub fn takes(&self, run: &RunSpec) -> bool {
        run.index % self.count as usize == self.index as usize
    }
}

impl FromStr for Shard {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        let parsed =
            s.split_once('/').and_then(|(i, n)| Some((i.trim().parse().ok()?, n.trim().parse().ok()?)));
        match parsed {
            Some((index, count)) if count >= 1 && index < count => Ok(Shard { index, count }),
            Some((index, count)) => Err(format!("shard {index}/{count}: need 0 <= I < N")),
            None => Err(format!("expected I/N (e.g. 0/4: the first of 4 shards), got {s:?}")),
        }
    }
}

impl fmt::Display for Shard {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}
