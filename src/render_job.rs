//! One render as `wavetrace render` makes it, for callers that are not its command line (the
//! Python package, issue 60): the settings and method options by the names configs and reports
//! use (the knob table, [`crate::options::knobs`], plus the render settings and the measurement
//! flags), then the same warm-up, render and [`RunReport`] as the command line, with the image
//! kept in memory instead of written to a file.

use anyhow::Result;
use serde_json::Value;

use crate::gpu::state::GpuMonitor;
use crate::gpu::GpuContext;
use crate::image_io::RgbImage;
use crate::method::{self, Method, MethodOptions, RenderOutput};
use crate::options::{self, knobs, DEFAULT_PREHEAT_SECONDS};
use crate::report::RunReport;
use crate::scene::Scene;
use crate::settings::{Accel, RenderSettings};
use crate::strict_json::{describe, did_you_mean, quoted_list};
use crate::warmup::{self, TimedWarmup, WarmupPolicy};

/// The names a job takes beside the knob table's: the render settings, then `wavetrace render`'s
/// measurement flags (`--instrument`, `--preheat`, `--warmup`, `--adapter`).
pub const SETTINGS: &[&str] =
    &["max_depth", "seed", "accel", "nee", "roulette", "instrument", "preheat", "warmup", "adapter"];

/// Every name [`RenderJob::set`] takes: [`SETTINGS`], then the knobs in the table's order.
pub fn option_names() -> Vec<&'static str> {
    SETTINGS.iter().copied().chain(knobs::KNOBS.iter().map(|k| k.name)).collect()
}

/// What to render and how, as `wavetrace render`'s flags give it.
#[derive(Clone, Debug, PartialEq)]
pub struct RenderJob {
    pub method: Method,
    pub settings: RenderSettings,
    pub options: MethodOptions,
    /// Adapter name substring (`--adapter`; None: the best adapter).
    pub adapter: Option<String>,
    /// Untimed frames before the timed one (`--warmup N`); None: `--warmup auto`.
    pub warmup: Option<u32>,
}

/// Which render a progress report is about.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Phase {
    WarmUp,
    Render,
}

/// A finished job: the film's mean as an image, the report `--report` writes, and the render.
pub struct Rendered {
    pub image: RgbImage,
    pub report: RunReport,
    pub output: RenderOutput,
}

impl RenderJob {
    /// The command line's defaults, at this size and spp.
    pub fn new(method: Method, width: u32, height: u32, spp: u32) -> Self {
        let options =
            MethodOptions { preheat_seconds: DEFAULT_PREHEAT_SECONDS, ..MethodOptions::requested() };
        let settings = RenderSettings { width, height, spp, ..RenderSettings::default() };
        Self { method, settings, options, adapter: None, warmup: None }
    }

    /// The method by name (`cpu`, `cpu-f64`, `megakernel`, `wavefront`).
    pub fn method(name: &str) -> Result<Method, String> {
        enum_value::<Method>("method", &Value::String(name.to_owned()))
    }

    /// Sets one option by its name; the error names it and says what it takes.
    pub fn set(&mut self, name: &str, v: &Value) -> Result<(), String> {
        let s = &mut self.settings;
        match name {
            "max_depth" => s.max_depth = whole(name, v)?,
            "seed" => s.seed = whole(name, v)?,
            "accel" => s.accel = enum_value::<Accel>(name, v)?,
            "nee" => s.nee = on_off(name, v)?,
            "roulette" => s.roulette = on_off(name, v)?,
            "instrument" => self.options.instrument = boolean(name, v)?,
            "preheat" => {
                let seconds =
                    v.as_f64().ok_or_else(|| format!("preheat: expected seconds, found {}", describe(v)))?;
                options::check_preheat(seconds).map_err(|e| format!("--preheat: {e}"))?;
                self.options.preheat_seconds = seconds;
            }
            "warmup" => self.warmup = warmup_frames(v)?,
            "adapter" => {
                self.adapter = match v {
                    Value::Null => None,
                    Value::String(a) => Some(a.clone()),
                    v => return Err(format!("adapter: expected a name or None, found {}", describe(v))),
                }
            }
            _ => {
                let knob = knobs::by_name(name).ok_or_else(|| {
                    format!("unknown option {name:?}{}", did_you_mean(name, &option_names()))
                })?;
                knob.set(&mut self.options, v).map_err(|e| format!("{name}: {e}"))?;
            }
        }
        Ok(())
    }

    /// Every option's value by name, as [`Self::set`] takes it back (a knob its method does not
    /// take is shown as the method it belongs to would record it).
    pub fn values(&self) -> serde_json::Map<String, Value> {
        let s = &self.settings;
        let mut out = serde_json::Map::new();
        out.insert("max_depth".into(), s.max_depth.into());
        out.insert("seed".into(), s.seed.into());
        out.insert("accel".into(), serde_json::to_value(s.accel).unwrap_or(Value::Null));
        out.insert("nee".into(), s.nee.into());
        out.insert("roulette".into(), s.roulette.into());
        out.insert("instrument".into(), self.options.instrument.into());
        out.insert("preheat".into(), self.options.preheat_seconds.into());
        out.insert("warmup".into(), self.warmup.map_or_else(|| "auto".into(), Value::from));
        out.insert("adapter".into(), self.adapter.clone().map_or(Value::Null, Value::from));
        for k in knobs::KNOBS {
            let method = if k.applies_to(self.method) { self.method } else { k.methods[k.methods.len() - 1] };
            out.insert(k.name.into(), k.get(&self.options, method));
        }
        out
    }

    /// Refuses what the command line refuses before rendering: settings no method can render,
    /// and knobs their method cannot run (the command line's wording, naming the flag).
    pub fn check(&self) -> Result<(), String> {
        self.settings.validate()?;
        options::check(self.method, &self.options).map_err(|e| e.for_cli())
    }
}

/// Renders `job` as `wavetrace render` does: a GPU context for GPU methods, the warm-up, the timed
/// render, its report. `on_progress` gets each render's finished path samples.
pub fn render(scene: &Scene, job: &RenderJob, on_progress: &(dyn Fn(Phase, u64) + Sync)) -> Result<Rendered> {
    let (method, settings, options) = (job.method, &job.settings, &job.options);
    let gpu = if method.needs_gpu() { Some(GpuContext::new(job.adapter.as_deref())?) } else { None };
    let policy = match (job.warmup, method.needs_gpu()) {
        (Some(n), _) => WarmupPolicy::Frames(n),
        (None, true) => WarmupPolicy::Timed(TimedWarmup::default()),
        (None, false) => WarmupPolicy::Frames(0),
    };
    let monitor = gpu.as_ref().and_then(|g| GpuMonitor::open(&g.summary));
    let warm = warmup::warm_up(
        &policy,
        0.0,
        || {
            let o = method::render(method, scene, settings, options, gpu.as_ref(), &|d| {
                on_progress(Phase::WarmUp, d)
            })?;
            Ok((o.seconds(), o.preheat_seconds()))
        },
        || monitor.as_ref().map(GpuMonitor::sample),
    )?;
    if warm.frames > 0 {
        log::info!("warm-up: {} frames, {:.3} s, settled: {}", warm.frames, warm.seconds, warm.settled);
    }
    let output =
        method::render(method, scene, settings, options, gpu.as_ref(), &|d| on_progress(Phase::Render, d))?;
    let mut report = RunReport::new(scene, method, settings, gpu.as_ref().map(|g| &g.summary), &output);
    report.warmup = Some(warm);
    let image = RgbImage { width: settings.width, height: settings.height, data: output.film.mean_rgb() };
    Ok(Rendered { image, report, output })
}

fn enum_value<T: clap::ValueEnum>(name: &str, v: &Value) -> Result<T, String> {
    let names: Vec<String> = T::value_variants()
        .iter()
        .filter_map(|x| x.to_possible_value())
        .map(|p| p.get_name().to_owned())
        .collect();
    let names: Vec<&str> = names.iter().map(String::as_str).collect();
    let s = v.as_str().ok_or_else(|| format!("{name}: expected a string, found {}", describe(v)))?;
    T::from_str(s, false).map_err(|_| {
        format!("{name}: unknown value {s:?}{}; expected {}", did_you_mean(s, &names), quoted_list(&names))
    })
}

fn whole(name: &str, v: &Value) -> Result<u32, String> {
    v.as_u64()
        .and_then(|x| u32::try_from(x).ok())
        .ok_or_else(|| format!("{name}: expected a whole number in 0..={}, found {}", u32::MAX, describe(v)))
}

fn boolean(name: &str, v: &Value) -> Result<bool, String> {
    v.as_bool().ok_or_else(|| format!("{name}: expected True or False, found {}", describe(v)))
}

/// `nee`, `roulette`: a boolean as configs write it, or `"on"` / `"off"` as the command line does.
fn on_off(name: &str, v: &Value) -> Result<bool, String> {
    match v {
        Value::Bool(b) => Ok(*b),
        Value::String(s) if s == "on" => Ok(true),
        Value::String(s) if s == "off" => Ok(false),
        v => Err(format!("{name}: expected True, False, \"on\" or \"off\", found {}", describe(v))),
    }
}

/// `warmup`: `"auto"` (None) or a number of frames.
fn warmup_frames(v: &Value) -> Result<Option<u32>, String> {
    match v {
        Value::String(s) if s == "auto" => Ok(None),
        v => whole("warmup", v).map(Some).map_err(|e| format!("{e} (or \"auto\")")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn names_set_the_fields_the_flags_set() {
        let mut job = RenderJob::new(Method::Wavefront, 8, 4, 2);
        for (name, v) in [
            ("max_depth", json!(7)),
            ("nee", json!("on")),
            ("roulette", json!(true)),
            ("accel", json!("none")),
            ("warmup", json!(0)),
            ("schedule", json!("regenerate")),
            ("tail", json!("megakernel")),
            ("translate", json!([1, 2, 3])),
        ] {
            job.set(name, &v).unwrap_or_else(|e| panic!("{name}: {e}"));
        }
        assert_eq!((job.settings.max_depth, job.settings.nee, job.settings.roulette), (7, true, true));
        assert_eq!((job.settings.accel, job.warmup), (Accel::None, Some(0)));
        assert_eq!(job.options.wavefront.tail, options::Tail::Megakernel);
        assert_eq!(job.options.stress.translate, [1.0, 2.0, 3.0]);
        job.check().unwrap();
    }

    #[test]
    fn every_value_reads_back_by_its_name() {
        let job = RenderJob::new(Method::Megakernel, 8, 4, 2);
        let values = job.values();
        assert_eq!(values.keys().map(String::as_str).collect::<Vec<_>>(), option_names());
        let mut again = RenderJob::new(Method::Megakernel, 8, 4, 2);
        for (name, v) in &values {
            again.set(name, v).unwrap_or_else(|e| panic!("{name}: {e}"));
        }
        assert_eq!(again, job);
        // Typed as the knob table records them: a fraction is a float even when whole.
        assert!(values["refill_below"].is_f64() && values["workgroup_size"].is_u64());
    }

    #[test]
    fn bad_names_and_values_are_named() {
        let mut job = RenderJob::new(Method::Wavefront, 8, 4, 2);
        assert_eq!(
            job.set("tial", &json!("off")).unwrap_err(),
            "unknown option \"tial\" (did you mean \"tail\"?)"
        );
        assert!(job.set("nee", &json!(3)).unwrap_err().starts_with("nee: expected True, False"));
        assert!(job.set("compaction", &json!("scna")).unwrap_err().contains("did you mean \"scan\""));
        job.set("tail", &json!("megakernel")).unwrap();
        assert_eq!(
            job.check().unwrap_err(),
            "--tail megakernel finishes regenerated paths: it needs --schedule regenerate"
        );
        assert_eq!(RenderJob::new(Method::Cpu, 0, 4, 1).check().unwrap_err(), "image size 0x4 is empty");
        assert!(RenderJob::method("gpu").unwrap_err().starts_with("method: unknown value \"gpu\""));
    }
}
