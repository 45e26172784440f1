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
use crate::input_error::InputError;
use crate::numerics::NumericOptions;
use crate::options::knobs::{self, Knob};
use crate::options::{self, Method, MethodOptions, Named};
use crate::scene::Scene;
use crate::settings::{Accel, RenderSettings};
use crate::strict_json::{describe, did_you_mean, join, parse_strict, quoted_list};
use crate::warmup::{TimedWarmup, WarmupPolicy};

/// The spread above which a run is flagged unstable unless the config says otherwise (here, not
/// in stability.rs, which reads reports: the config is read first and imports nothing above it).
pub const DEFAULT_UNSTABLE_SPREAD: f64 = 0.05;

/// The `schema` tag this build reads.
pub const CONFIG_SCHEMA: &str = "wavetrace-experiment/1";

pub(crate) const TOP_FIELDS: &[&str] = &[
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
            .optional(root, "preheat_seconds", |v, p| self.number(v, p, 0.0, options::MAX_PREHEAT_SECONDS))?
            .unwrap_or(options::DEFAULT_PREHEAT_SECONDS);
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
                        let why = crate::scene::builtin::unknown_scene(&arg, &file);
                        return self
                            .err(&path, format!("{why} (scene files are found relative to the config)"));
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

    /// One `methods[i]` entry: the product of its knobs' values (one each unless swept), each
    /// variant labelled by the knobs that tell it apart (swept ones and, without a label, ones
    /// set away from their defaults), less the combinations `options::check` refuses.
    fn method_entry(&self, v: &Value, path: &str) -> Res<Vec<MethodVariant>> {
        let o = self.object(v, path)?;
        let method = self.method(self.field(o, path, "method")?, &join(path, "method"))?;
        self.only_knobs(o, path, method)?;
        let label = self.optional(o, "label", |v, p| self.string(v, p).map(str::to_owned))?;
        if label.as_deref().is_some_and(|l| l.trim().is_empty()) {
            return self.err(&join(path, "label"), "must not be empty");
        }
        let defaults = MethodOptions::requested();
        let name = label.clone().unwrap_or_else(|| method.name().to_owned());
        let mut variants = vec![(defaults.clone(), vec![name])];
        for knob in knobs::of(method) {
            let Some(given) = o.get(knob.name) else { continue };
            let (values, swept) = self.knob_values(knob, method, given, &join(path, knob.name), &defaults)?;
            let mut out = Vec::with_capacity(variants.len() * values.len());
            for (options, parts) in &variants {
                for value in &values {
                    let (mut o, mut p) = (options.clone(), parts.clone());
                    knob.set(&mut o, value).expect("each value was read once already");
                    if swept || (label.is_none() && knob.get(&o, method) != knob.get(&defaults, method)) {
                        p.push(knob.label(&o, method));
                    }
                    out.push((o, p));
                }
            }
            variants = out;
        }
        // A combination the rules refuse is dropped; a value it was refused for that no other
        // combination keeps is an error, at that knob.
        let (kept, refused): (Vec<_>, Vec<_>) = variants
            .into_iter()
            .map(|(o, p)| (options::check(method, &o), o, p))
            .partition(|(c, ..)| c.is_ok());
        for (e, o) in refused.iter().filter_map(|(c, o, _)| Some((c.as_ref().err()?, o))) {
            let knob = knobs::by_name(e.knob).expect("rules name knobs");
            if !kept.iter().any(|(_, k, _)| knob.get(k, method) == knob.get(o, method)) {
                return self.err(&join(path, e.knob), e.for_config());
            }
        }
        Ok(kept
            .into_iter()
            .map(|(_, options, parts)| MethodVariant { label: parts.join(" "), method, options })
            .collect())
    }

    /// An entry's fields: `method`, `label` and the method's knobs.
    fn only_knobs(&self, o: &Map<String, Value>, path: &str, method: Method) -> Res<()> {
        let mut allowed = vec!["method", "label"];
        allowed.extend(knobs::of(method).map(|k| k.name));
        let Some(k) = o.keys().find(|k| !allowed.contains(&k.as_str())) else { return Ok(()) };
        let reason = if knobs::by_name(k).is_some() {
            format!("{} has no knob {k:?}; its knobs are {}", method.name(), quoted_list(&allowed[2..]))
        } else {
            format!("unknown field{}; expected {}", did_you_mean(k, &allowed), quoted_list(&allowed))
        };
        self.err(&join(path, k), reason)
    }

    /// A knob's values as the entry gives them (one, or a list: swept when longer than one),
    /// each read and checked alone against its range, without repeats.
    fn knob_values(
        &self,
        knob: &Knob,
        method: Method,
        given: &Value,
        path: &str,
        defaults: &MethodOptions,
    ) -> Res<(Vec<Value>, bool)> {
        let (values, list) = match knob.values(given) {
            Some([]) => return self.err(path, "must not be empty"),
            Some(items) => (items.to_vec(), true),
            None => (vec![given.clone()], false),
        };
        let mut seen = Vec::new();
        for (i, v) in values.iter().enumerate() {
            let at = if list { format!("{path}[{i}]") } else { path.to_owned() };
            let mut o = defaults.clone();
            knob.set(&mut o, v).map_err(|reason| self.error(&at, reason))?;
            match options::check(method, &o) {
                Err(e) if e.is_range() && e.knob == knob.name => return self.err(&at, e.for_config()),
                _ => {}
            }
            let value = knob.get(&o, method);
            if seen.contains(&value) {
                return self.err(&at, "repeats an earlier value");
            }
            seen.push(value);
        }
        Ok((values, list && seen.len() > 1))
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
        // The numerical knobs, read as the methods' are.
        let mut read = MethodOptions::default();
        for k in ["ray_offset", "sphere_hit", "fresnel"].into_iter().filter_map(knobs::by_name) {
            if let Some(v) = o.get(k.name) {
                k.set(&mut read, v).map_err(|reason| self.error(&join("reference", k.name), reason))?;
            }
        }
        // The reference is the untransformed scene: where it is rendered hardly matters, and
        // cpu-f64 always renders in camera space.
        let numerics = NumericOptions { render_space: Default::default(), ..read.numerics };
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

    /// A method name, as `wavetrace render --method` spells it.
    fn method(&self, v: &Value, path: &str) -> Res<Method> {
        use clap::ValueEnum;
        let names: Vec<String> = Method::value_variants().iter().map(Named::name).collect();
        let names: Vec<&str> = names.iter().map(String::as_str).collect();
        let name = self.string(v, path)?;
        Method::from_str(name, false).map_err(|_| {
            self.error(
                path,
                format!(
                    "unknown value {name:?}{}; expected {}",
                    did_you_mean(name, &names),
                    quoted_list(&names)
                ),
            )
        })
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
