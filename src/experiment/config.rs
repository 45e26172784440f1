//! Experiment configs (`"schema": "wavetrace-experiment/1"`): what to render, how often, and what
//! to measure error against. Read strictly, like scene files: unknown fields, duplicate keys and
//! out-of-range values are errors naming the file, the JSON path and the reason, and the whole
//! config (scenes, reference EXRs, every run's settings) is checked before anything renders.
//!
//! ```json
//! {
//!   "schema": "wavetrace-experiment/1",
//!   "question": "Does the wavefront beat the megakernel on the book's final scene?",
//!   "scenes": ["rtiow-final", "scenes/my_scene.json"],
//!   "resolutions": ["400x225"],
//!   "spp": [4, 16, 64],
//!   "max_depth": [50],
//!   "nee": [false, true],
//!   "roulette": [false, true],
//!   "seed": 0,
//!   "accel": "bvh",
//!   "repetitions": 3,
//!   "warmup": {"min_seconds": 0.5, "agree": 0.05, "max_frames": 50, "max_seconds": 10},
//!   "interleave": true,
//!   "preheat_seconds": 0.2,
//!   "unstable_spread": 0.05,
//!   "instrument": false,
//!   "methods": [
//!     {"method": "cpu", "light_sampling": ["area", "solid-angle"]},
//!     {"method": "megakernel", "workgroup_size": [32, 64, 128]},
//!     {"method": "wavefront", "label": "wf", "compaction": ["atomic", "scan"], "shade": "single"}
//!   ],
//!   "reference": {"method": "cpu-f64", "spp": 1024},
//!   "metrics": {"trim": 0.0, "flip": true}
//! }
//! ```
//!
//! Required: `schema`, `question`, `scenes`, `resolutions`, `spp`, `methods`. Every other field
//! has the default shown in [`ExperimentConfig`]'s docs. A knob given as a list is swept: each
//! value becomes its own method variant. See the README's "Experiments" section for every field.
//!
//! # Numerical knobs and stress transforms (every method)
//!
//! As `wavetrace render`'s `--ray-offset`, `--sphere-hit`, `--fresnel`, `--scale`, `--translate`:
//!
//! - `ray_offset`: `"tmin"` (the book's 1e-3), `"tmin=VALUE"` (VALUE finite and ≥ 0) or
//!   `"robust"`; label `ray-offset=robust`, `ray-offset=tmin=1e-4`.
//! - `sphere_hit`: `"book"` or `"stable"` (default); label `sphere-hit=book`.
//! - `render_space`: `"camera"` (default: the scene moved in f64 so the camera is at the origin
//!   before it is stored in f32) or `"world"`; label `render-space=world`.
//! - `fresnel`: `"schlick"` (default) or `"exact"`; label `fresnel=exact`.
//! - `scale`: a number > 0 inside f32's range (default 1); label `scale=1e-4`.
//! - `translate`: a number D, meaning (D, D, D), or an array `[x, y, z]` (default 0); each
//!   coordinate must fit in f32. Label `translate=1e5`, or `translate=1,2,3` when the coordinates
//!   differ. **A list is a sweep, except that an array of exactly three numbers is one vector**
//!   (`[1, 2, 3]` is the translation (1, 2, 3), as `--translate 1,2,3`). In a sweep each entry is
//!   a number D, a one-number array `[D]` (both (D, D, D)) or `[x, y, z]`: `[0, 1e3, 1e5, 1e7]`
//!   sweeps four distances, `[0, [1, 2, 3]]` two translations, and three distances are written
//!   `[[0], [1e3], [1e5]]` (or `[0, 1e3, [1e5]]`). A variant's label shows the vector it got, so a
//!   three-number array meant as a sweep is visible as `translate=0,1000,100000`.
//!
//! The scene (geometry, camera, textures' space) is scaled, then moved, before every render of
//! the variant; the image is the same in exact arithmetic, so what differs from the reference is
//! numerical error. Each variant's transform is applied to each scene when the config is read:
//! one that overflows f32 is refused there.
//!
//! # The reference
//!
//! `{"method": M, "spp": N, "max_depth": D, "seed": S, "nee": B, "roulette": B, "ray_offset": …,
//! "sphere_hit": …, "fresnel": …}`: rendered once per (scene, resolution), cached. The numerical
//! knobs (each one value, defaults as on the methods) say how the reference itself computes; it
//! never takes `scale` or `translate`: the reference is always the untransformed scene, which is
//! what the stress transforms are measured against.
//!
//! `"spp": "match"` renders a reference for each run instead: at the run's own spp, max depth,
//! NEE, roulette, seed and light knobs (`light_sampling`, `light_select`), so that run and
//! reference trace the same random numbers and their difference is numerical error, not noise
//! (e.g. `cpu` against a matched `cpu-f64` is f32's error alone). `seed`, `max_depth`, `nee` and
//! `roulette` are then refused (they are the run's). Matched references are cached per spp (the cache key holds the settings and
//! every knob away from its default). Or `{"exr": "refs/{scene}-{width}x{height}.exr"}`.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

use serde_json::{Map, Value};

use super::overrides::Override;
use super::stability::DEFAULT_UNSTABLE_SPREAD;
use crate::gpu::megakernel::MegakernelOptions;
use crate::gpu::shader_checks::ShaderChecks;
use crate::gpu::specialize::Specialize;
use crate::gpu::timing::Timing;
use crate::gpu::wavefront::{
    Append, CompactStates, Compaction, ComputePasses, QueueOrder, RaySort, Scan, Schedule, ShadePasses, Tail,
    WavefrontOptions,
};
use crate::input_error::InputError;
use crate::light_options::{LightOptions, LightSampling, LightSelect};
use crate::method::{Method, MethodOptions};
use crate::numerics::{Fresnel, NumericOptions, RayOffset, SphereHit};
use crate::render_space::RenderSpace;
use crate::scene::stress::StressTransform;
use crate::scene::Scene;
use crate::settings::{Accel, RenderSettings};
use crate::strict_json::{describe, did_you_mean, join, parse_strict, quoted_list};
use crate::warmup::{TimedWarmup, WarmupPolicy};

/// The `schema` tag this build reads.
pub const CONFIG_SCHEMA: &str = "wavetrace-experiment/1";

const TOP_FIELDS: &[&str] = &[
    "schema",
    "question",
    "scenes",
    "resolutions",
    "spp",
    "max_depth",
    "nee",
    "roulette",
    "seed",
    "accel",
    "repetitions",
    "warmup",
    "interleave",
    "preheat_seconds",
    "unstable_spread",
    "instrument",
    "adapter",
    "methods",
    "reference",
    "metrics",
];
const METHOD_NAMES: &[&str] = &["cpu", "cpu-f64", "megakernel", "wavefront"];
const COMPACTIONS: &[&str] = &["atomic", "scan", "off"];
const SHADES: &[&str] = &["per-material", "per-texture", "single"];
const SCHEDULES: &[&str] = &["auto", "waves", "regenerate"];
const TAILS: &[&str] = &["off", "megakernel"];
const TIMINGS: &[&str] = &["passes", "frame"];

/// Every method knob a config can set, in the order runs.csv gives them columns.
/// Knobs a later build adds go at the end, so existing columns keep their places.
pub const KNOBS: &[&str] = &[
    "workgroup_size",
    "samples_per_dispatch",
    "pool_size",
    "compaction",
    "shade",
    "schedule",
    "sync_every",
    "tail",
    "tail_threshold",
    "scan",
    "append",
    "timing",
    "light_sampling",
    "light_select",
    "threads",
    "ray_offset",
    "sphere_hit",
    "fresnel",
    "scale",
    "translate",
    "chunk_pools",
    "render_space",
    "queue_order",
    "refill_below",
    "compact_states",
    "ray_sort",
    "compute_passes",
    "shader_checks",
    "specialize",
    "batches_in_flight",
];
/// Every method's knobs: how next-event estimation samples lights, the numerical choices and the
/// stress transforms.
const CPU_KNOBS: &[&str] = &[
    "light_sampling",
    "light_select",
    "ray_offset",
    "sphere_hit",
    "fresnel",
    "render_space",
    "scale",
    "translate",
];
const MEGAKERNEL_KNOBS: &[&str] = &[
    "light_sampling",
    "light_select",
    "ray_offset",
    "sphere_hit",
    "fresnel",
    "render_space",
    "scale",
    "translate",
    "workgroup_size",
    "samples_per_dispatch",
    "schedule",
    "threads",
    "timing",
    "shader_checks",
    "specialize",
];
const WAVEFRONT_KNOBS: &[&str] = &[
    "light_sampling",
    "light_select",
    "ray_offset",
    "sphere_hit",
    "fresnel",
    "render_space",
    "scale",
    "translate",
    "workgroup_size",
    "pool_size",
    "compaction",
    "shade",
    "schedule",
    "sync_every",
    "batches_in_flight",
    "tail",
    "tail_threshold",
    "chunk_pools",
    "scan",
    "append",
    "queue_order",
    "refill_below",
    "compact_states",
    "ray_sort",
    "compute_passes",
    "timing",
    "shader_checks",
    "specialize",
];
const SCANS: &[&str] = &["auto", "subgroup", "workgroup"];
const APPENDS: &[&str] = &["auto", "lane", "subgroup"];
const ON_OFF: &[&str] = &["off", "on"];
const RAY_SORTS: &[&str] = &["off", "octant", "octant-cell"];
const COMPUTE_PASSES: &[&str] = &["per-dispatch", "shared"];
const SHADER_CHECKS: &[&str] = &["checked", "unchecked"];
const SPECIALIZES: &[&str] = &["scene", "none"];
const QUEUE_ORDERS: &[&str] = &["auto", "arrival", "slot", "slot-depth"];
const LIGHT_SAMPLINGS: &[&str] = &["area", "solid-angle"];
const LIGHT_SELECTS: &[&str] = &["uniform", "power"];
const SPHERE_HITS: &[&str] = &["book", "stable"];
const FRESNELS: &[&str] = &["schlick", "exact"];
const RENDER_SPACES: &[&str] = &["camera", "world"];
/// What `translate` takes, for its errors.
const TRANSLATE_FORMS: &str = "expected a number D (the translation (D, D, D)) or an array [x, y, z]; \
a list of these is a sweep, except that an array of exactly three numbers is one vector [x, y, z] \
(sweep three distances as [[a], [b], [c]])";
/// The reference's fields.
const REFERENCE_FIELDS: &[&str] =
    &["method", "spp", "max_depth", "seed", "nee", "roulette", "ray_offset", "sphere_hit", "fresnel"];
/// Repetitions and warm-ups above this are almost certainly typos (and would take forever).
const MAX_REPETITIONS: u32 = 1000;

/// A scene as the config names it, and the scene it resolved to.
#[derive(Clone, Debug)]
pub struct SceneEntry {
    /// As written in the config (a built-in name or a path relative to the config file).
    pub arg: String,
    pub scene: Scene,
}

/// One method with one value of each knob.
#[derive(Clone, Debug, PartialEq)]
pub struct MethodVariant {
    /// Unique within the config: the entry's `label` (or method name), plus `knob=value` for
    /// the swept knobs and, without a label, the knobs set away from their defaults.
    pub label: String,
    pub method: Method,
    pub options: MethodOptions,
}

/// What the runs are measured against.
#[derive(Clone, Debug, PartialEq)]
pub enum ReferenceSpec {
    /// Render with `method`, computing as `numerics` say, always on the untransformed scene;
    /// cached on disk.
    Render { method: Method, samples: ReferenceSamples, numerics: NumericOptions },
    /// Read EXRs: `pattern` with `{scene}`, `{width}`, `{height}` replaced, relative to the config.
    Exr { pattern: String },
}

/// Which renders a rendered reference is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ReferenceSamples {
    /// `"spp": N`: one reference per (scene, resolution), at these settings, with the default
    /// light knobs.
    Fixed { spp: u32, max_depth: u32, seed: u32, nee: bool, roulette: bool },
    /// `"spp": "match"`: one reference per run, at the run's own spp, max depth, NEE, roulette,
    /// seed and light knobs, so that both trace the same random numbers: their difference is numerical
    /// error, not noise.
    Match,
}

impl ReferenceSpec {
    /// What the reference of a run rendered with `run` and `options` is rendered with: method,
    /// settings and knobs (`None` for EXR references). Never a stress transform: the reference
    /// is the untransformed scene.
    pub fn render_for(
        &self,
        run: &RenderSettings,
        options: &MethodOptions,
    ) -> Option<(Method, RenderSettings, MethodOptions)> {
        let ReferenceSpec::Render { method, samples, numerics } = *self else { return None };
        let mut o = MethodOptions { numerics, ..MethodOptions::default() };
        let settings = match samples {
            ReferenceSamples::Fixed { spp, max_depth, seed, nee, roulette } => {
                RenderSettings { spp, max_depth, seed, nee, roulette, ..run.clone() }
            }
            ReferenceSamples::Match => {
                o.lights = options.lights;
                run.clone()
            }
        };
        Some((method, settings, o))
    }
}

/// Error-metric options (`metrics`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MetricOptions {
    /// Fraction of the largest per-pixel errors dropped from each metric (FLIP excepted).
    pub trim: f64,
    /// Compute mean LDR-FLIP.
    pub flip: bool,
}

/// A validated experiment config.
#[derive(Clone, Debug)]
pub struct ExperimentConfig {
    /// The file it was read from.
    pub file: PathBuf,
    /// The config as written, echoed into the report.
    pub raw: Value,
    /// The `--set` overrides applied to the file (already in `raw`), as given.
    pub overrides: Vec<String>,
    /// The file's stem.
    pub name: String,
    /// The question the experiment answers (one sentence).
    pub question: String,
    pub scenes: Vec<SceneEntry>,
    /// (width, height) pairs.
    pub resolutions: Vec<(u32, u32)>,
    pub spp: Vec<u32>,
    /// Default `[50]` (the book's).
    pub max_depth: Vec<u32>,
    /// Next-event estimation off and/or on (default `[false]`).
    pub nee: Vec<bool>,
    /// Russian roulette off and/or on (default `[false]`, the book's full-length paths).
    pub roulette: Vec<bool>,
    /// Default 0.
    pub seed: u32,
    /// Default `bvh`.
    pub accel: Accel,
    /// Timed renders per run (default 3); the report gives their median, min and max.
    pub repetitions: u32,
    /// Untimed renders before the timed ones: clocks, pipeline caches, page faults.
    pub warmup: WarmupSpec,
    /// The GPU variants of one job (scene and settings) take turns, repetition by repetition
    /// (A B C, A B C), so that drift in the GPU's clocks hits each alike (default true).
    pub interleave: bool,
    /// GPU methods: seconds of busy GPU work just before each frame (warm-up and timed), so
    /// every frame starts at the clocks continuous rendering holds (`gpu::preheat`; default 0.2,
    /// 0 turns it off; never on a software adapter).
    pub preheat_seconds: f64,
    /// A run whose repetitions spread by more than this fraction of their median is flagged
    /// unstable (default 0.05).
    pub unstable_spread: f64,
    /// Also render each GPU run once with subgroup counters for SIMD efficiency (default false).
    pub instrument: bool,
    /// Adapter name substring (default: the best adapter).
    pub adapter: Option<String>,
    pub methods: Vec<MethodVariant>,
    /// Default none (no error metrics).
    pub reference: Option<ReferenceSpec>,
    pub metrics: MetricOptions,
}

impl ExperimentConfig {
    /// Reads and validates a config file.
    pub fn from_file(path: &Path) -> Result<Self, InputError> {
        Self::from_file_with(path, &[])
    }

    /// [`Self::from_file`] with `--set` overrides applied to the file's JSON before it is read.
    pub fn from_file_with(path: &Path, overrides: &[Override]) -> Result<Self, InputError> {
        let file = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|e| InputError {
            file: file.clone(),
            path: String::new(),
            reason: format!("cannot read the file: {e}"),
        })?;
        Self::from_str_with(&text, path, overrides)
    }

    /// Reads a config from text; `path` locates relative scene and reference paths and labels
    /// errors.
    pub fn from_str(text: &str, path: &Path) -> Result<Self, InputError> {
        Self::from_str_with(text, path, &[])
    }

    /// [`Self::from_str`] with `--set` overrides: each is applied in order, then the result is
    /// validated as a file is; an error at a field an override set names it.
    pub fn from_str_with(text: &str, path: &Path, overrides: &[Override]) -> Result<Self, InputError> {
        let cx =
            Cx { file: path.display().to_string(), dir: path.parent().unwrap_or(Path::new("")).to_owned() };
        let mut raw = parse_strict(text).map_err(|(p, reason)| cx.error(&p, reason))?;
        for o in overrides {
            o.apply(&mut raw).map_err(|reason| cx.error(&o.path(), format!("--set {}: {reason}", o.text)))?;
        }
        let mut config = cx.config(&raw, path).map_err(|mut e| {
            // The last override that set the field, or a field inside it.
            let inside = |p: &str| {
                e.path == p || e.path.starts_with(&format!("{p}.")) || e.path.starts_with(&format!("{p}["))
            };
            if let Some(o) = overrides.iter().rev().find(|o| inside(&o.path())) {
                e.reason = format!("{} (set by --set {})", e.reason, o.text);
            }
            e
        })?;
        config.overrides = overrides.iter().map(|o| o.text.clone()).collect();
        Ok(config)
    }

    /// Every run's render settings, in plan order: resolution, then max depth, then next-event
    /// estimation, then roulette, then spp.
    pub fn settings(&self) -> impl Iterator<Item = RenderSettings> + '_ {
        self.resolutions.iter().flat_map(move |&(width, height)| {
            self.max_depth.iter().flat_map(move |&max_depth| {
                self.nee.iter().flat_map(move |&nee| {
                    self.roulette.iter().flat_map(move |&roulette| {
                        self.spp.iter().map(move |&spp| RenderSettings {
                            width,
                            height,
                            spp,
                            max_depth,
                            seed: self.seed,
                            accel: self.accel,
                            nee,
                            roulette,
                        })
                    })
                })
            })
        })
    }

    /// The reference EXR for a scene and resolution (`reference.exr` configs only).
    pub fn reference_exr(&self, scene: &str, width: u32, height: u32) -> Option<PathBuf> {
        match &self.reference {
            Some(ReferenceSpec::Exr { pattern }) => {
                let dir = self.file.parent().unwrap_or(Path::new(""));
                Some(dir.join(expand_pattern(pattern, scene, width, height)))
            }
            _ => None,
        }
    }
}

/// `warmup` as a config gives it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum WarmupSpec {
    /// Not given: a timed warm-up with the default targets for GPU methods, one frame for CPU
    /// methods.
    Default,
    /// A number: exactly that many untimed frames for every method (0: none; such runs are
    /// reported cold).
    Frames(u32),
    /// An object: a timed warm-up with these targets for GPU methods, one frame for CPU methods.
    Timed(TimedWarmup),
}

impl WarmupSpec {
    /// How `method` warms up under this spec.
    pub fn policy(&self, method: Method) -> WarmupPolicy {
        match (*self, method.needs_gpu()) {
            (WarmupSpec::Frames(n), _) => WarmupPolicy::Frames(n),
            (WarmupSpec::Default, true) => WarmupPolicy::Timed(TimedWarmup::default()),
            (WarmupSpec::Timed(t), true) => WarmupPolicy::Timed(t),
            (_, false) => WarmupPolicy::Frames(1),
        }
    }
}

/// `{scene}`, `{width}`, `{height}` replaced.
pub fn expand_pattern(pattern: &str, scene: &str, width: u32, height: u32) -> String {
    pattern
        .replace("{scene}", scene)
        .replace("{width}", &width.to_string())
        .replace("{height}", &height.to_string())
}

type Res<T> = Result<T, InputError>;

struct Cx {
    file: String,
    /// The config's directory: relative paths in it are relative to this.
    dir: PathBuf,
}

impl Cx {
    fn error(&self, path: &str, reason: impl Into<String>) -> InputError {
        InputError { file: self.file.clone(), path: path.to_owned(), reason: reason.into() }
    }

    fn err<T>(&self, path: &str, reason: impl Into<String>) -> Res<T> {
        Err(self.error(path, reason))
    }

    fn config(&self, raw: &Value, path: &Path) -> Res<ExperimentConfig> {
        let root = self.object(raw, "")?;
        let Some(schema) = root.get("schema") else {
            return self.err(
                "",
                format!("missing required field \"schema\" (expected \"schema\": \"{CONFIG_SCHEMA}\")"),
            );
        };
        let schema = self.string(schema, "schema")?;
        if schema != CONFIG_SCHEMA {
            return self.err(
                "schema",
                format!("unsupported schema {schema:?}; this build reads \"{CONFIG_SCHEMA}\""),
            );
        }
        self.only(root, "", TOP_FIELDS)?;

        let question = self.string(self.field(root, "", "question")?, "question")?.trim().to_owned();
        if question.is_empty() {
            return self.err("question", "say in one sentence what question the experiment answers");
        }
        let scenes = self.scenes(self.field(root, "", "scenes")?)?;
        let resolutions =
            self.list(self.field(root, "", "resolutions")?, "resolutions", |v, p| self.resolution(v, p))?;
        let spp = self.list(self.field(root, "", "spp")?, "spp", |v, p| self.uint32(v, p, 1, u32::MAX))?;
        let max_depth = match root.get("max_depth") {
            Some(v) => self.list(v, "max_depth", |v, p| self.uint32(v, p, 1, (1 << 24) - 1))?,
            None => vec![RenderSettings::default().max_depth],
        };
        let nee = match root.get("nee") {
            Some(v) => self.list(v, "nee", |v, p| self.boolean(v, p))?,
            None => vec![false],
        };
        let roulette = match root.get("roulette") {
            Some(v) => self.list(v, "roulette", |v, p| self.boolean(v, p))?,
            None => vec![false],
        };
        let seed = self.optional(root, "seed", |v, p| self.uint32(v, p, 0, u32::MAX))?.unwrap_or(0);
        let accel = match self.optional(root, "accel", |v, p| self.choice(v, p, &["bvh", "none"]))? {
            Some("none") => Accel::None,
            _ => Accel::Bvh,
        };
        let repetitions =
            self.optional(root, "repetitions", |v, p| self.uint32(v, p, 1, MAX_REPETITIONS))?.unwrap_or(3);
        let warmup = self.optional(root, "warmup", |v, p| self.warmup(v, p))?.unwrap_or(WarmupSpec::Default);
        let interleave = self.optional(root, "interleave", |v, p| self.boolean(v, p))?.unwrap_or(true);
        let preheat_seconds = self
            .optional(root, "preheat_seconds", |v, p| {
                self.number(v, p, 0.0, crate::gpu::preheat::MAX_SECONDS)
            })?
            .unwrap_or(crate::gpu::preheat::DEFAULT_SECONDS);
        let unstable_spread = self
            .optional(root, "unstable_spread", |v, p| self.number(v, p, 0.0, 10.0))?
            .unwrap_or(DEFAULT_UNSTABLE_SPREAD);
        let instrument = self.optional(root, "instrument", |v, p| self.boolean(v, p))?.unwrap_or(false);
        let adapter = self.optional(root, "adapter", |v, p| self.string(v, p).map(str::to_owned))?;
        let methods = self.methods(self.field(root, "", "methods")?, &scenes)?;
        let max_max_depth = *max_depth.iter().max().expect("lists are non-empty");
        let reference = match root.get("reference") {
            None | Some(Value::Null) => None,
            Some(v) => Some(self.reference(v, seed, max_max_depth)?),
        };
        let metrics = self.metrics(root.get("metrics"))?;

        let config = ExperimentConfig {
            file: path.to_owned(),
            raw: raw.clone(),
            overrides: Vec::new(),
            name: path.file_stem().map_or_else(|| "experiment".into(), |s| s.to_string_lossy().into_owned()),
            question,
            scenes,
            resolutions,
            spp,
            max_depth,
            nee,
            roulette,
            seed,
            accel,
            repetitions,
            warmup,
            interleave,
            preheat_seconds,
            unstable_spread,
            instrument,
            adapter,
            methods,
            reference,
            metrics,
        };
        for s in config.settings() {
            s.validate().map_err(|r| self.error("resolutions", format!("{}x{}: {r}", s.width, s.height)))?;
        }
        self.check_reference_files(&config)?;
        Ok(config)
    }

    fn scenes(&self, v: &Value) -> Res<Vec<SceneEntry>> {
        let args = self.list(v, "scenes", |v, p| self.string(v, p).map(str::to_owned))?;
        let mut seen = BTreeSet::new();
        let mut out = Vec::new();
        for (i, arg) in args.into_iter().enumerate() {
            let path = format!("scenes[{i}]");
            let scene = match crate::scene::builtin::by_name(&arg) {
                Some(s) => s,
                None => {
                    let file = self.dir.join(&arg);
                    if !file.exists() {
                        return self.err(&path, crate::scene::builtin::unknown_scene(&arg, &file));
                    }
                    crate::scene::Scene::from_path(&file)
                        .map_err(|e| self.error(&path, format!("in the scene file: {e}")))?
                }
            };
            if !seen.insert(scene.name.clone()) {
                return self.err(
                    &path,
                    format!("a second scene named {:?}; runs are keyed by scene name", scene.name),
                );
            }
            out.push(SceneEntry { arg, scene });
        }
        Ok(out)
    }

    fn resolution(&self, v: &Value, path: &str) -> Res<(u32, u32)> {
        let text = self.string(v, path)?;
        let parsed = text
            .split_once('x')
            .and_then(|(w, h)| Some((w.trim().parse::<u32>().ok()?, h.trim().parse::<u32>().ok()?)));
        match parsed {
            Some((w, h)) if w > 0 && h > 0 => Ok((w, h)),
            _ => self.err(
                path,
                format!("expected \"WIDTHxHEIGHT\" with both at least 1, e.g. \"400x225\", found {text:?}"),
            ),
        }
    }

    fn methods(&self, v: &Value, scenes: &[SceneEntry]) -> Res<Vec<MethodVariant>> {
        let Value::Array(items) = v else {
            return self
                .err("methods", format!("expected an array of method objects, found {}", describe(v)));
        };
        if items.is_empty() {
            return self.err("methods", "name at least one method");
        }
        let mut out: Vec<MethodVariant> = Vec::new();
        for (i, item) in items.iter().enumerate() {
            let path = format!("methods[{i}]");
            for variant in self.method_entry(item, &path)? {
                if out.iter().any(|o| o.label == variant.label) {
                    return self.err(
                        &path,
                        format!(
                            "method label {:?} is used twice; give each entry its own \"label\"",
                            variant.label
                        ),
                    );
                }
                self.check_stress(&variant, scenes, &path)?;
                out.push(variant);
            }
        }
        Ok(out)
    }

    /// A variant's stress transform applied to every scene, so that one that overflows f32 is
    /// refused before anything renders.
    fn check_stress(&self, v: &MethodVariant, scenes: &[SceneEntry], path: &str) -> Res<()> {
        let t = &v.options.stress;
        if t.is_identity() {
            return Ok(());
        }
        let field = if t.scale != 1.0 { "scale" } else { "translate" };
        for s in scenes {
            if let Err(e) = t.apply(&s.scene) {
                return self.err(
                    &join(path, field),
                    format!(
                        "variant {:?} (scale {:e}, translate {:?}) on scene {:?}: {e}",
                        v.label, t.scale, t.translate, s.scene.name
                    ),
                );
            }
        }
        Ok(())
    }

    /// One `methods[i]` entry, expanded over its swept knobs.
    fn method_entry(&self, v: &Value, path: &str) -> Res<Vec<MethodVariant>> {
        let o = self.object(v, path)?;
        let mpath = join(path, "method");
        let method = self.method(self.field(o, path, "method")?, &mpath)?;
        let knobs: &[&str] = match method {
            Method::Cpu | Method::CpuF64 => CPU_KNOBS,
            Method::Megakernel => MEGAKERNEL_KNOBS,
            Method::Wavefront => WAVEFRONT_KNOBS,
        };
        let mut allowed = vec!["method", "label"];
        allowed.extend_from_slice(knobs);
        if let Some(k) = o.keys().find(|k| !allowed.contains(&k.as_str())) {
            let reason = if KNOBS.contains(&k.as_str()) {
                format!(
                    "{} has no knob {k:?}; its knobs are {}",
                    method.name(),
                    if knobs.is_empty() { "none".into() } else { quoted_list(knobs) }
                )
            } else {
                format!("unknown field{}; expected {}", did_you_mean(k, &allowed), quoted_list(&allowed))
            };
            return self.err(&join(path, k), reason);
        }
        let label = self.optional(o, "label", |v, p| self.string(v, p).map(str::to_owned))?;
        let label_path = join(path, "label");
        if label.as_deref().is_some_and(|l| l.trim().is_empty()) {
            return self.err(&label_path, "must not be empty");
        }

        // Each knob: its values (one unless swept), and whether it was swept.
        let opt_path = |k: &str| join(path, k);
        let light_sampling = self.knob(o, &opt_path("light_sampling"), "light_sampling", |v, p| {
            Ok(if self.choice(v, p, LIGHT_SAMPLINGS)? == "area" {
                LightSampling::Area
            } else {
                LightSampling::SolidAngle
            })
        })?;
        let light_select = self.knob(o, &opt_path("light_select"), "light_select", |v, p| {
            Ok(if self.choice(v, p, LIGHT_SELECTS)? == "uniform" {
                LightSelect::Uniform
            } else {
                LightSelect::Power
            })
        })?;
        let ray_offset = self.knob(o, &opt_path("ray_offset"), "ray_offset", |v, p| self.ray_offset(v, p))?;
        let sphere_hit = self.knob(o, &opt_path("sphere_hit"), "sphere_hit", |v, p| self.sphere_hit(v, p))?;
        let fresnel = self.knob(o, &opt_path("fresnel"), "fresnel", |v, p| self.fresnel(v, p))?;
        let render_space =
            self.knob(o, &opt_path("render_space"), "render_space", |v, p| self.render_space(v, p))?;
        let scale = self.knob(o, &opt_path("scale"), "scale", |v, p| self.scale(v, p))?;
        let translate = self.translate_knob(o, &opt_path("translate"))?;
        let wg =
            self.knob(o, &opt_path("workgroup_size"), "workgroup_size", |v, p| self.uint32(v, p, 1, 1024))?;
        let spd = self.knob(o, &opt_path("samples_per_dispatch"), "samples_per_dispatch", |v, p| {
            self.uint(v, p, 1, u64::MAX)
        })?;
        // A count, or null for the method's default.
        let count_or_default = |v: &Value, p: &str| match v {
            Value::Null => Ok(None),
            _ => self.uint32(v, p, 1, u32::MAX).map(Some),
        };
        let threads = self.knob(o, &opt_path("threads"), "threads", count_or_default)?;
        let pool = self.knob(o, &opt_path("pool_size"), "pool_size", count_or_default)?;
        let compaction = self.knob(o, &opt_path("compaction"), "compaction", |v, p| {
            Ok(match self.choice(v, p, COMPACTIONS)? {
                "atomic" => Compaction::Atomic,
                "scan" => Compaction::Scan,
                _ => Compaction::Off,
            })
        })?;
        let shade = self.knob(o, &opt_path("shade"), "shade", |v, p| {
            Ok(match self.choice(v, p, SHADES)? {
                "single" => ShadePasses::Single,
                "per-texture" => ShadePasses::PerTexture,
                _ => ShadePasses::PerMaterial,
            })
        })?;

        let schedule = self.knob(o, &opt_path("schedule"), "schedule", |v, p| {
            Ok(match self.choice(v, p, SCHEDULES)? {
                "regenerate" => Schedule::Regenerate,
                "waves" => Schedule::Waves,
                _ => Schedule::Auto,
            })
        })?;
        let sync_every = self.knob(o, &opt_path("sync_every"), "sync_every", |v, p| {
            self.uint32(v, p, 1, crate::gpu::wavefront::schedule::MAX_SYNC_EVERY)
        })?;
        let batches_in_flight =
            self.knob(o, &opt_path("batches_in_flight"), "batches_in_flight", |v, p| {
                self.uint32(v, p, 1, crate::gpu::wavefront::MAX_BATCHES_IN_FLIGHT)
            })?;
        let tail = self.knob(o, &opt_path("tail"), "tail", |v, p| {
            Ok(if self.choice(v, p, TAILS)? == "megakernel" { Tail::Megakernel } else { Tail::Off })
        })?;
        let tail_threshold =
            self.knob(o, &opt_path("tail_threshold"), "tail_threshold", |v, p| match v.as_f64() {
                Some(t) if t > 0.0 && t <= 1.0 => Ok(t),
                _ => self.err(p, format!("must be a fraction of the pool in (0, 1], got {}", describe(v))),
            })?;
        let chunk_pools = self.knob(o, &opt_path("chunk_pools"), "chunk_pools", |v, p| {
            self.uint32(v, p, 1, crate::gpu::wavefront::schedule::MAX_CHUNK_POOLS)
        })?;
        let scan = self.knob(o, &opt_path("scan"), "scan", |v, p| {
            Ok(match self.choice(v, p, SCANS)? {
                "subgroup" => Scan::Subgroup,
                "workgroup" => Scan::Workgroup,
                _ => Scan::Auto,
            })
        })?;
        let append = self.knob(o, &opt_path("append"), "append", |v, p| {
            Ok(match self.choice(v, p, APPENDS)? {
                "subgroup" => Append::Subgroup,
                "lane" => Append::Lane,
                _ => Append::Auto,
            })
        })?;
        let queue_order = self.knob(o, &opt_path("queue_order"), "queue_order", |v, p| {
            Ok(match self.choice(v, p, QUEUE_ORDERS)? {
                "slot" => QueueOrder::Slot,
                "slot-depth" => QueueOrder::SlotDepth,
                "arrival" => QueueOrder::Arrival,
                _ => QueueOrder::Auto,
            })
        })?;
        let refill_below =
            self.knob(o, &opt_path("refill_below"), "refill_below", |v, p| match v.as_f64() {
                Some(t) if t > 0.0 && t <= 1.0 => Ok(t),
                _ => {
                    self.err(p, format!("must be a live fraction of the pool in (0, 1], got {}", describe(v)))
                }
            })?;
        let compact_states = self.knob(o, &opt_path("compact_states"), "compact_states", |v, p| {
            Ok(if self.choice(v, p, ON_OFF)? == "on" { CompactStates::On } else { CompactStates::Off })
        })?;
        let ray_sort = self.knob(o, &opt_path("ray_sort"), "ray_sort", |v, p| {
            Ok(match self.choice(v, p, RAY_SORTS)? {
                "octant" => RaySort::Octant,
                "octant-cell" => RaySort::OctantCell,
                _ => RaySort::Off,
            })
        })?;
        let compute_passes = self.knob(o, &opt_path("compute_passes"), "compute_passes", |v, p| {
            Ok(match self.choice(v, p, COMPUTE_PASSES)? {
                "per-dispatch" => ComputePasses::PerDispatch,
                _ => ComputePasses::Shared,
            })
        })?;
        let shader_checks = self.knob(o, &opt_path("shader_checks"), "shader_checks", |v, p| {
            Ok(match self.choice(v, p, SHADER_CHECKS)? {
                "unchecked" => ShaderChecks::Unchecked,
                _ => ShaderChecks::Checked,
            })
        })?;
        let specialize = self.knob(o, &opt_path("specialize"), "specialize", |v, p| {
            Ok(if self.choice(v, p, SPECIALIZES)? == "none" { Specialize::None } else { Specialize::Scene })
        })?;
        let timing = self.knob(o, &opt_path("timing"), "timing", |v, p| {
            Ok(if self.choice(v, p, TIMINGS)? == "frame" { Timing::Frame } else { Timing::Passes })
        })?;
        if tail.values.contains(&Tail::Megakernel) && !schedule.values.contains(&Schedule::Regenerate) {
            return self.err(
                &opt_path("tail"),
                "\"megakernel\" finishes regenerated paths: it needs \"schedule\": \"regenerate\"",
            );
        }

        if let Some(slot) = queue_order.values.iter().find(|q| q.is_slot()) {
            // Not given means the default, atomic appends: only an explicit "off" everywhere lacks queues.
            if !compaction.values.is_empty() && compaction.values.iter().all(|&c| c == Compaction::Off) {
                return self.err(
                    &opt_path("queue_order"),
                    format!(
                        "\"{}\" orders the queues, and \"compaction\": \"off\" has none: it needs \"atomic\" or \"scan\"",
                        slot.name()
                    ),
                );
            }
        }

        if let Some(sort) = ray_sort.values.iter().find(|&&r| r != RaySort::Off) {
            if !compaction.values.is_empty() && compaction.values.iter().all(|&c| c == Compaction::Off) {
                return self.err(
                    &opt_path("ray_sort"),
                    format!(
                        "\"{}\" sorts the ray queue, and \"compaction\": \"off\" has none: it needs \"atomic\" or \"scan\"",
                        sort.name()
                    ),
                );
            }
        }

        if refill_below.values.iter().any(|&r| r != WavefrontOptions::default().refill_below)
            && !schedule.values.contains(&Schedule::Regenerate)
        {
            return self.err(
                &opt_path("refill_below"),
                "batched refills are the regenerating schedule's: it needs \"schedule\": \"regenerate\"",
            );
        }
        if compact_states.values.contains(&CompactStates::On) {
            if !schedule.values.contains(&Schedule::Regenerate) {
                return self.err(
                    &opt_path("compact_states"),
                    "\"on\" compacts the pool before refills: it needs \"schedule\": \"regenerate\"",
                );
            }
            if !compaction.values.is_empty() && compaction.values.iter().all(|&c| c == Compaction::Off) {
                return self.err(
                    &opt_path("compact_states"),
                    "\"on\" rewrites the ray queue's entries of the paths it moves, and \"compaction\": \"off\" has \
                     none: it needs \"atomic\" or \"scan\"",
                );
            }
        }

        if chunk_pools.values.iter().any(|&c| c != WavefrontOptions::default().chunk_pools)
            && !schedule.values.contains(&Schedule::Regenerate)
        {
            return self.err(
                &opt_path("chunk_pools"),
                "the sample ring is the regenerating schedule's: it needs \"schedule\": \"regenerate\"",
            );
        }

        if threads.values.iter().any(Option::is_some) && !schedule.values.contains(&Schedule::Regenerate) {
            return self.err(
                &opt_path("threads"),
                "persistent threads belong to the regenerating megakernel: it needs \"schedule\": \"regenerate\"",
            );
        }

        // The product of every knob's values, each variant labelled by the knobs that tell it
        // apart: swept ones, and (without a label) ones set away from their defaults.
        let mk = MegakernelOptions::default();
        let wf = WavefrontOptions::default();
        // A method that names no schedule takes `auto`, as the command line does (the library's
        // Default is the plain waves, the baseline its tests compare against).
        let schedule_default = Schedule::Auto;
        let mut defaults = MethodOptions::default();
        defaults.megakernel.schedule = schedule_default;
        defaults.wavefront.schedule = schedule_default;
        let mut variants = vec![(defaults, vec![label.clone().unwrap_or_else(|| method.name().to_owned())])];
        let labelled = label.is_some();
        let lights = LightOptions::default();
        expand(&mut variants, &light_sampling, lights.sampling, labelled, |o, &l| {
            o.lights.sampling = l;
            format!("light-sampling={}", l.name())
        });
        expand(&mut variants, &light_select, lights.select, labelled, |o, &l| {
            o.lights.select = l;
            format!("light-select={}", l.name())
        });
        expand(&mut variants, &wg, mk.workgroup_size, labelled, |o, &w| {
            o.megakernel.workgroup_size = w;
            o.wavefront.workgroup_size = w;
            format!("wg={w}")
        });
        expand(&mut variants, &spd, mk.samples_per_dispatch, labelled, |o, &s| {
            o.megakernel.samples_per_dispatch = s;
            format!("spd={s}")
        });
        expand(&mut variants, &threads, mk.threads, labelled, |o, &t| {
            o.megakernel.threads = t;
            format!("threads={}", t.map_or("auto".into(), |t| t.to_string()))
        });
        expand(&mut variants, &pool, wf.pool_size, labelled, |o, &p| {
            o.wavefront.pool_size = p;
            format!("pool={}", p.map_or("auto".into(), |p| p.to_string()))
        });
        expand(&mut variants, &compaction, wf.compaction, labelled, |o, &c| {
            o.wavefront.compaction = c;
            format!("compaction={}", kebab(&c))
        });
        expand(&mut variants, &shade, wf.shade, labelled, |o, &sh| {
            o.wavefront.shade = sh;
            format!("shade={}", kebab(&sh))
        });
        expand(&mut variants, &schedule, schedule_default, labelled, |o, &sc| {
            o.megakernel.schedule = sc;
            o.wavefront.schedule = sc;
            format!("schedule={}", kebab(&sc))
        });
        expand(&mut variants, &sync_every, wf.sync_every, labelled, |o, &k| {
            o.wavefront.sync_every = k;
            format!("sync={k}")
        });
        expand(&mut variants, &batches_in_flight, wf.batches_in_flight, labelled, |o, &k| {
            o.wavefront.batches_in_flight = k;
            format!("in_flight={k}")
        });
        expand(&mut variants, &tail, wf.tail, labelled, |o, &t| {
            o.wavefront.tail = t;
            format!("tail={}", kebab(&t))
        });
        expand(&mut variants, &tail_threshold, wf.tail_threshold, labelled, |o, &t| {
            o.wavefront.tail_threshold = t;
            format!("tail-threshold={t}")
        });
        expand(&mut variants, &chunk_pools, wf.chunk_pools, labelled, |o, &c| {
            o.wavefront.chunk_pools = c;
            format!("chunk-pools={c}")
        });
        expand(&mut variants, &scan, wf.scan, labelled, |o, &sc| {
            o.wavefront.scan = sc;
            format!("scan={}", kebab(&sc))
        });
        expand(&mut variants, &append, wf.append, labelled, |o, &a| {
            o.wavefront.append = a;
            format!("append={}", kebab(&a))
        });
        expand(&mut variants, &queue_order, wf.queue_order, labelled, |o, &q| {
            o.wavefront.queue_order = q;
            format!("queue-order={}", kebab(&q))
        });
        expand(&mut variants, &refill_below, wf.refill_below, labelled, |o, &r| {
            o.wavefront.refill_below = r;
            format!("refill-below={r}")
        });
        expand(&mut variants, &compact_states, wf.compact_states, labelled, |o, &c| {
            o.wavefront.compact_states = c;
            format!("compact-states={}", kebab(&c))
        });
        expand(&mut variants, &ray_sort, wf.ray_sort, labelled, |o, &r| {
            o.wavefront.ray_sort = r;
            format!("ray-sort={}", r.name())
        });
        expand(&mut variants, &compute_passes, wf.compute_passes, labelled, |o, &c| {
            o.wavefront.compute_passes = c;
            format!("compute-passes={}", c.name())
        });
        expand(&mut variants, &shader_checks, ShaderChecks::Checked, labelled, |o, &c| {
            o.shader_checks = c;
            format!("shader-checks={}", c.name())
        });
        expand(&mut variants, &specialize, Specialize::Scene, labelled, |o, &s| {
            o.specialize = s;
            format!("specialize={}", s.name())
        });
        expand(&mut variants, &timing, Timing::Passes, labelled, |o, &t| {
            o.timing = t;
            format!("timing={}", kebab(&t))
        });
        let numerics = NumericOptions::default();
        let stress = StressTransform::default();
        expand(&mut variants, &ray_offset, numerics.ray_offset, labelled, |o, &r| {
            o.numerics.ray_offset = r;
            format!("ray-offset={}", r.name())
        });
        expand(&mut variants, &sphere_hit, numerics.sphere_hit, labelled, |o, &h| {
            o.numerics.sphere_hit = h;
            format!("sphere-hit={}", h.name())
        });
        expand(&mut variants, &fresnel, numerics.fresnel, labelled, |o, &f| {
            o.numerics.fresnel = f;
            format!("fresnel={}", f.name())
        });
        expand(&mut variants, &render_space, numerics.render_space, labelled, |o, &r| {
            o.numerics.render_space = r;
            format!("render-space={}", r.name())
        });
        expand(&mut variants, &scale, stress.scale, labelled, |o, &s| {
            o.stress.scale = s;
            format!("scale={}", compact(s))
        });
        expand(&mut variants, &translate, stress.translate, labelled, |o, &t| {
            o.stress.translate = t;
            format!("translate={}", translate_name(t))
        });
        // A tail only means something when regenerating: a product that pairs it with waves
        // would not run.
        variants
            .retain(|(o, _)| o.wavefront.tail == Tail::Off || o.wavefront.schedule == Schedule::Regenerate);
        // Likewise slot order, which needs queues.
        variants
            .retain(|(o, _)| !o.wavefront.queue_order.is_slot() || o.wavefront.compaction != Compaction::Off);
        variants.retain(|(o, _)| {
            o.wavefront.ray_sort == RaySort::Off || o.wavefront.compaction != Compaction::Off
        });
        // Likewise a pass per pattern, which needs atomic queues.
        variants.retain(|(o, _)| {
            o.wavefront.shade != ShadePasses::PerTexture || o.wavefront.compaction == Compaction::Atomic
        });
        // Likewise batched refills and state compaction (which also needs queues).
        variants.retain(|(o, _)| {
            let w = &o.wavefront;
            (w.refill_below == wf.refill_below && w.compact_states == CompactStates::Off)
                || (w.schedule == Schedule::Regenerate
                    && (w.compact_states == CompactStates::Off || w.compaction != Compaction::Off))
        });
        // Likewise chunk sizes, which only the regenerating wavefront has.
        variants.retain(|(o, _)| {
            o.wavefront.chunk_pools == wf.chunk_pools || o.wavefront.schedule == Schedule::Regenerate
        });
        // Likewise persistent threads, which only the regenerating megakernel has.
        variants
            .retain(|(o, _)| o.megakernel.threads.is_none() || o.megakernel.schedule == Schedule::Regenerate);
        let out = variants
            .into_iter()
            .map(|(options, parts)| MethodVariant { label: parts.join(" "), method, options })
            .collect();
        Ok(out)
    }

    fn reference(&self, v: &Value, seed: u32, max_depth: u32) -> Res<ReferenceSpec> {
        let o = self.object(v, "reference")?;
        if o.contains_key("exr") {
            self.only(o, "reference", &["exr"])?;
            let pattern = self.string(self.field(o, "reference", "exr")?, "reference.exr")?.to_owned();
            return Ok(ReferenceSpec::Exr { pattern });
        }
        for k in ["scale", "translate"] {
            if o.contains_key(k) {
                return self.err(
                    &join("reference", k),
                    "the reference is always the untransformed scene: the stress transforms are \
                     measured against it (give \"scale\" and \"translate\" to the methods)",
                );
            }
        }
        self.only(o, "reference", REFERENCE_FIELDS)?;
        let method = self.method(self.field(o, "reference", "method")?, "reference.method")?;
        let numerics = NumericOptions {
            ray_offset: self
                .optional(o, "ray_offset", |v, _| self.ray_offset(v, "reference.ray_offset"))?
                .unwrap_or_default(),
            sphere_hit: self
                .optional(o, "sphere_hit", |v, _| self.sphere_hit(v, "reference.sphere_hit"))?
                .unwrap_or_default(),
            fresnel: self
                .optional(o, "fresnel", |v, _| self.fresnel(v, "reference.fresnel"))?
                .unwrap_or_default(),
            // The reference is the untransformed scene: where it is rendered hardly matters, and
            // cpu-f64 always renders in camera space.
            render_space: Default::default(),
        };
        let spp_value = self.field(o, "reference", "spp")?;
        if spp_value.as_str() == Some("match") {
            if let Some(k) = ["seed", "max_depth", "nee", "roulette"].into_iter().find(|k| o.contains_key(*k))
            {
                return self.err(
                    &join("reference", k),
                    "with \"spp\": \"match\" the reference takes each run's own spp, seed, max depth, \
                     NEE and roulette, so that both trace the same random numbers; drop this field",
                );
            }
            return Ok(ReferenceSpec::Render { method, samples: ReferenceSamples::Match, numerics });
        }
        let spp = match spp_value {
            Value::String(s) => {
                return self.err(
                    "reference.spp",
                    format!("expected a whole number in 1..={} or \"match\", found {s:?}", u32::MAX),
                )
            }
            v => self.uint32(v, "reference.spp", 1, u32::MAX)?,
        };
        let max_depth =
            self.optional(o, "max_depth", |v, p| self.uint32(v, p, 1, (1 << 24) - 1))?.unwrap_or(max_depth);
        // The counter-based RNG would trace a run's paths again in the reference with the same
        // seed, and the error would be underestimated; so the default seed differs.
        let ref_seed =
            self.optional(o, "seed", |v, p| self.uint32(v, p, 0, u32::MAX))?.unwrap_or(seed.wrapping_add(1));
        if ref_seed == seed {
            return self.err(
                "reference.seed",
                format!("equals the runs' seed ({seed}): the reference would trace the runs' own paths and hide their error; choose another seed (or \"spp\": \"match\", which does so on purpose)"),
            );
        }
        // Next-event estimation converges to the same image; on, a reference of lit scenes
        // such as cornell needs far fewer samples.
        let nee = self.optional(o, "nee", |v, p| self.boolean(v, p))?.unwrap_or(false);
        // Roulette is unbiased too, so one reference serves runs with it off and on; off (the
        // default) spends the reference's time on full-length paths, the lower-variance choice.
        let roulette = self.optional(o, "roulette", |v, p| self.boolean(v, p))?.unwrap_or(false);
        let samples = ReferenceSamples::Fixed { spp, max_depth, seed: ref_seed, nee, roulette };
        Ok(ReferenceSpec::Render { method, samples, numerics })
    }

    fn metrics(&self, v: Option<&Value>) -> Res<MetricOptions> {
        let mut m = MetricOptions { trim: 0.0, flip: true };
        let Some(v) = v else { return Ok(m) };
        let o = self.object(v, "metrics")?;
        self.only(o, "metrics", &["trim", "flip"])?;
        if let Some(t) = o.get("trim") {
            let x = t.as_f64().ok_or_else(|| {
                self.error("metrics.trim", format!("expected a number, found {}", describe(t)))
            })?;
            if !(0.0..1.0).contains(&x) {
                return self.err("metrics.trim", format!("must be in [0, 1), got {x}"));
            }
            m.trim = x;
        }
        if let Some(f) = o.get("flip") {
            m.flip = self.boolean(f, "metrics.flip")?;
        }
        Ok(m)
    }

    /// EXR references must exist and match every resolution before anything renders.
    fn check_reference_files(&self, c: &ExperimentConfig) -> Res<()> {
        for s in &c.scenes {
            for &(w, h) in &c.resolutions {
                let Some(file) = c.reference_exr(&s.scene.name, w, h) else { return Ok(()) };
                let (image, _) = crate::image_io::read_exr(&file).map_err(|e| {
                    self.error(
                        "reference.exr",
                        format!("reference for scene {:?} at {w}x{h}: {e}", s.scene.name),
                    )
                })?;
                if (image.width, image.height) != (w, h) {
                    return self.err(
                        "reference.exr",
                        format!(
                            "{} is {}x{}, but the runs of scene {:?} are {w}x{h}",
                            file.display(),
                            image.width,
                            image.height,
                            s.scene.name
                        ),
                    );
                }
            }
        }
        Ok(())
    }

    // -- Field helpers ----------------------------------------------------------------------

    fn object<'v>(&self, v: &'v Value, path: &str) -> Res<&'v Map<String, Value>> {
        match v {
            Value::Object(m) => Ok(m),
            _ => self.err(path, format!("expected an object, found {}", describe(v))),
        }
    }

    fn field<'v>(&self, o: &'v Map<String, Value>, path: &str, key: &str) -> Res<&'v Value> {
        o.get(key).ok_or_else(|| self.error(path, format!("missing required field \"{key}\"")))
    }

    fn only(&self, o: &Map<String, Value>, path: &str, allowed: &[&str]) -> Res<()> {
        match o.keys().find(|k| !allowed.contains(&k.as_str())) {
            None => Ok(()),
            Some(k) => self.err(
                &join(path, k),
                format!("unknown field{}; expected {}", did_you_mean(k, allowed), quoted_list(allowed)),
            ),
        }
    }

    fn optional<T>(
        &self,
        o: &Map<String, Value>,
        key: &str,
        read: impl Fn(&Value, &str) -> Res<T>,
    ) -> Res<Option<T>> {
        o.get(key).map(|v| read(v, key)).transpose()
    }

    /// A non-empty list (a single value is a list of one), without repeats.
    fn list<T: PartialEq>(
        &self,
        v: &Value,
        path: &str,
        read: impl Fn(&Value, &str) -> Res<T>,
    ) -> Res<Vec<T>> {
        let out = match v {
            Value::Array(items) if items.is_empty() => return self.err(path, "must not be empty"),
            Value::Array(items) => items
                .iter()
                .enumerate()
                .map(|(i, x)| read(x, &format!("{path}[{i}]")))
                .collect::<Res<Vec<T>>>()?,
            _ => vec![read(v, path)?],
        };
        if let Some(i) = (1..out.len()).find(|&i| out[..i].contains(&out[i])) {
            return self.err(&format!("{path}[{i}]"), "repeats an earlier value");
        }
        Ok(out)
    }

    /// A method knob: absent, one value, or a list (swept).
    fn knob<T: PartialEq>(
        &self,
        o: &Map<String, Value>,
        path: &str,
        key: &str,
        read: impl Fn(&Value, &str) -> Res<T>,
    ) -> Res<Knob<T>> {
        Ok(match o.get(key) {
            None => Knob { values: Vec::new(), swept: false },
            Some(v @ Value::Array(_)) => {
                let values = self.list(v, path, read)?;
                Knob { swept: values.len() > 1, values }
            }
            Some(v) => Knob { values: vec![read(v, path)?], swept: false },
        })
    }

    /// `"tmin"`, `"tmin=VALUE"` or `"robust"`.
    fn ray_offset(&self, v: &Value, path: &str) -> Res<RayOffset> {
        RayOffset::parse(self.string(v, path)?).map_err(|e| self.error(path, e))
    }

    fn sphere_hit(&self, v: &Value, path: &str) -> Res<SphereHit> {
        Ok(if self.choice(v, path, SPHERE_HITS)? == "book" { SphereHit::Book } else { SphereHit::Stable })
    }

    fn render_space(&self, v: &Value, path: &str) -> Res<RenderSpace> {
        Ok(if self.choice(v, path, RENDER_SPACES)? == "world" {
            RenderSpace::World
        } else {
            RenderSpace::Camera
        })
    }

    fn fresnel(&self, v: &Value, path: &str) -> Res<Fresnel> {
        Ok(if self.choice(v, path, FRESNELS)? == "exact" { Fresnel::Exact } else { Fresnel::Schlick })
    }

    /// A scale factor: a number > 0 inside f32's range.
    fn scale(&self, v: &Value, path: &str) -> Res<f64> {
        let Some(scale) = v.as_f64() else {
            return self
                .err(path, format!("expected a number > 0 (the scale factor), found {}", describe(v)));
        };
        StressTransform { scale, ..Default::default() }.validate().map_err(|e| self.error(path, e))?;
        Ok(scale)
    }

    /// One translation: a number D for (D, D, D), `[D]` likewise, or `[x, y, z]`.
    fn translate(&self, v: &Value, path: &str) -> Res<[f64; 3]> {
        let number = |v: &Value, p: &str| v.as_f64().ok_or_else(|| self.error(p, TRANSLATE_FORMS));
        let translate = match v {
            Value::Number(_) => [number(v, path)?; 3],
            Value::Array(a) if a.len() == 1 => [number(&a[0], &format!("{path}[0]"))?; 3],
            Value::Array(a) if a.len() == 3 => {
                let c = |i: usize| number(&a[i], &format!("{path}[{i}]"));
                [c(0)?, c(1)?, c(2)?]
            }
            _ => return self.err(path, format!("{TRANSLATE_FORMS}; found {}", describe(v))),
        };
        StressTransform { translate, ..Default::default() }.validate().map_err(|e| self.error(path, e))?;
        Ok(translate)
    }

    /// `translate` as a knob: one value, or a list swept, where an array of exactly three numbers
    /// is one vector, not a sweep (see the module docs).
    fn translate_knob(&self, o: &Map<String, Value>, path: &str) -> Res<Knob<[f64; 3]>> {
        match o.get("translate") {
            Some(v @ Value::Array(a)) if a.len() == 3 && a.iter().all(Value::is_number) => {
                Ok(Knob { values: vec![self.translate(v, path)?], swept: false })
            }
            _ => self.knob(o, path, "translate", |v, p| self.translate(v, p)),
        }
    }

    fn string<'v>(&self, v: &'v Value, path: &str) -> Res<&'v str> {
        v.as_str().ok_or_else(|| self.error(path, format!("expected a string, found {}", describe(v))))
    }

    /// A number in `min..=max`.
    fn number(&self, v: &Value, path: &str, min: f64, max: f64) -> Res<f64> {
        match v.as_f64() {
            Some(x) if (min..=max).contains(&x) => Ok(x),
            Some(x) => self.err(path, format!("must be in [{min}, {max}], got {x}")),
            None => self.err(path, format!("expected a number in [{min}, {max}], found {}", describe(v))),
        }
    }

    /// `warmup`: a whole number of frames, or the timed warm-up's targets as an object.
    fn warmup(&self, v: &Value, path: &str) -> Res<WarmupSpec> {
        if !v.is_object() {
            return match v.as_u64() {
                Some(n) if n <= u64::from(MAX_REPETITIONS) => Ok(WarmupSpec::Frames(n as u32)),
                _ => self.err(
                    path,
                    format!(
                        "expected a whole number of frames in 0..={MAX_REPETITIONS}, or {{\"min_seconds\", \
                         \"agree\", \"max_frames\", \"max_seconds\"}} for a timed warm-up; found {}",
                        describe(v)
                    ),
                ),
            };
        }
        let o = self.object(v, path)?;
        self.only(o, path, &["min_seconds", "agree", "max_frames", "max_seconds"])?;
        let d = TimedWarmup::default();
        let at = |k: &str| join(path, k);
        let num = |k: &str, min: f64, max: f64, default: f64| -> Res<f64> {
            o.get(k).map_or(Ok(default), |x| self.number(x, &at(k), min, max))
        };
        let t = TimedWarmup {
            min_seconds: num("min_seconds", 0.0, 3600.0, d.min_seconds)?,
            agree: num("agree", 0.0, 10.0, d.agree)?,
            max_frames: o
                .get("max_frames")
                .map_or(Ok(d.max_frames), |x| self.uint32(x, &at("max_frames"), 1, MAX_REPETITIONS))?,
            max_seconds: num("max_seconds", 0.0, 3600.0, d.max_seconds)?,
        };
        Ok(WarmupSpec::Timed(t))
    }

    fn boolean(&self, v: &Value, path: &str) -> Res<bool> {
        v.as_bool().ok_or_else(|| self.error(path, format!("expected true or false, found {}", describe(v))))
    }

    fn uint(&self, v: &Value, path: &str, min: u64, max: u64) -> Res<u64> {
        match v.as_u64() {
            Some(x) if (min..=max).contains(&x) => Ok(x),
            Some(x) => self.err(path, format!("must be in {min}..={max}, got {x}")),
            None => {
                self.err(path, format!("expected a whole number in {min}..={max}, found {}", describe(v)))
            }
        }
    }

    fn uint32(&self, v: &Value, path: &str, min: u32, max: u32) -> Res<u32> {
        self.uint(v, path, min.into(), max.into()).map(|x| x as u32)
    }

    /// A method name (`METHOD_NAMES`, as `Method::name` spells them).
    fn method(&self, v: &Value, path: &str) -> Res<Method> {
        let name = self.choice(v, path, METHOD_NAMES)?;
        Ok([Method::Cpu, Method::CpuF64, Method::Megakernel, Method::Wavefront]
            .into_iter()
            .find(|m| m.name() == name)
            .expect("METHOD_NAMES lists every method's name"))
    }

    fn choice(&self, v: &Value, path: &str, options: &[&'static str]) -> Res<&'static str> {
        let s = self.string(v, path)?;
        options.iter().find(|&&o| o == s).copied().ok_or_else(|| {
            self.error(
                path,
                format!("unknown value {s:?}{}; expected {}", did_you_mean(s, options), quoted_list(options)),
            )
        })
    }
}

/// A knob's values as given; empty when the entry leaves it at its default.
struct Knob<T> {
    values: Vec<T>,
    swept: bool,
}

impl<T> Knob<T> {
    fn given(&self) -> bool {
        !self.values.is_empty()
    }

    fn values_or<'a>(&'a self, default: &'a [T]) -> &'a [T] {
        if self.values.is_empty() {
            default
        } else {
            &self.values
        }
    }
}

/// Replaces each variant by one per value of `knob` (or the default, if not given), applying the
/// value with `set`, which also names it; the name joins the label when the knob was swept, or
/// given away from its default in an unlabelled entry.
fn expand<T: PartialEq>(
    variants: &mut Vec<(MethodOptions, Vec<String>)>,
    knob: &Knob<T>,
    default: T,
    labelled: bool,
    set: impl Fn(&mut MethodOptions, &T) -> String,
) {
    let default = [default];
    let values = knob.values_or(&default);
    let mut out = Vec::with_capacity(variants.len() * values.len());
    for (options, parts) in variants.drain(..) {
        for v in values {
            let mut o = options.clone();
            let mut p = parts.clone();
            let name = set(&mut o, v);
            if knob.swept || (!labelled && knob.given() && *v != default[0]) {
                p.push(name);
            }
            out.push((o, p));
        }
    }
    *variants = out;
}

/// A number as labels show it: plain from 0.01 to 999 (`0.5`, `250`), else in exponent form
/// (`1e-3`, `1e3`, `2.5e7`).
pub fn compact(v: f64) -> String {
    if v == 0.0 || (1e-2..1e3).contains(&v.abs()) {
        format!("{v}")
    } else {
        format!("{v:e}")
    }
}

/// A translation as labels show it: `1e5` for (1e5, 1e5, 1e5), else `x,y,z`.
pub fn translate_name(t: [f64; 3]) -> String {
    if t[0] == t[1] && t[1] == t[2] {
        compact(t[0])
    } else {
        t.map(compact).join(",")
    }
}

/// A knob value as the config spells it (`"per-material"`).
fn kebab<T: serde::Serialize>(v: &T) -> String {
    serde_json::to_value(v).ok().and_then(|v| v.as_str().map(str::to_owned)).unwrap_or_default()
}
