//! Every method knob an experiment config can set, in one table: its name (the config's key,
//! the report's and runs.csv's column), the methods that take it, its label in variant names,
//! and where it lives in [`MethodOptions`]. Configs read knobs through it, reports write them
//! through it, and variant labels are made by it; adding a knob is a field in the options and a
//! row here (and a rule in `check.rs` if it needs one).

use super::{
    Append, CompactStates, Compaction, ComputePasses, Launch, Method, MethodOptions, Named, PoolSize,
    QueueOrder, RaySort, Refill, Scan, Schedule, ShadePasses, ShaderChecks, ShadowRays, Specialize, Tail,
    Timing,
};
use crate::bvh::collapse::Collapse;
use crate::bvh::stack::BvhStack;
use crate::bvh::BvhLayout;
use crate::light_options::{LightSampling, LightSelect};
use crate::numerics::{Fresnel, RayOffset, SphereHit};
use crate::render_space::RenderSpace;
use crate::scene::stress::StressTransform;
use crate::strict_json::{describe, did_you_mean, quoted_list};
use serde_json::Value;

/// One knob.
pub struct Knob {
    /// As configs, reports and runs.csv spell it.
    pub name: &'static str,
    /// Its part of a variant's label (`wg` in `wg=64`).
    pub label: &'static str,
    /// The methods that take it.
    pub methods: &'static [Method],
    /// Reads one value into the options (the reason when it cannot be read).
    set: fn(&mut MethodOptions, &Value) -> Result<(), String>,
    /// The value as reports record it, for a method.
    get: fn(&MethodOptions, Method) -> Value,
    /// The value as labels show it, for a method.
    show: fn(&MethodOptions, Method) -> String,
}

impl Knob {
    pub fn set(&self, o: &mut MethodOptions, v: &Value) -> Result<(), String> {
        (self.set)(o, v)
    }

    pub fn get(&self, o: &MethodOptions, method: Method) -> Value {
        (self.get)(o, method)
    }

    /// `wg=64`.
    pub fn label(&self, o: &MethodOptions, method: Method) -> String {
        format!("{}={}", self.label, (self.show)(o, method))
    }

    pub fn applies_to(&self, method: Method) -> bool {
        self.methods.contains(&method)
    }

    /// Its values as a config writes them: one value, or a list (a sweep). `translate` takes a
    /// vector of three numbers as one value (a list of three numbers is one translation).
    pub fn values<'v>(&self, v: &'v Value) -> Option<&'v [Value]> {
        match v {
            Value::Array(a) if self.name == "translate" && a.len() == 3 && a.iter().all(Value::is_number) => {
                None
            }
            Value::Array(a) => Some(a),
            _ => None,
        }
    }
}

/// A knob's value type: how a config writes it and a label shows it.
trait KnobValue: Sized + serde::Serialize {
    fn read(v: &Value) -> Result<Self, String>;
    fn show(&self) -> String;
}

macro_rules! enum_values {
    ($($t:ty),*) => {$(
        impl KnobValue for $t {
            fn read(v: &Value) -> Result<Self, String> {
                use clap::ValueEnum;
                let names: Vec<String> = Self::value_variants().iter().map(|x| Named::name(x)).collect();
                let names: Vec<&str> = names.iter().map(String::as_str).collect();
                let s = v.as_str().ok_or_else(|| format!("expected a string, found {}", describe(v)))?;
                Self::from_str(s, false).map_err(|_| {
                    format!("unknown value {s:?}{}; expected {}", did_you_mean(s, &names), quoted_list(&names))
                })
            }
            fn show(&self) -> String {
                Named::name(self)
            }
        }
    )*};
}

enum_values!(
    Compaction,
    ShadePasses,
    Schedule,
    Tail,
    Scan,
    Append,
    QueueOrder,
    CompactStates,
    RaySort,
    ComputePasses,
    Launch,
    ShadowRays,
    Refill,
    ShaderChecks,
    Specialize,
    Timing,
    LightSampling,
    LightSelect,
    SphereHit,
    Fresnel,
    RenderSpace,
    BvhLayout,
    Collapse,
    BvhStack
);

impl KnobValue for u32 {
    fn read(v: &Value) -> Result<Self, String> {
        v.as_u64()
            .and_then(|x| u32::try_from(x).ok())
            .ok_or_else(|| format!("expected a whole number in 0..={}, found {}", u32::MAX, describe(v)))
    }
    fn show(&self) -> String {
        self.to_string()
    }
}

impl KnobValue for u64 {
    fn read(v: &Value) -> Result<Self, String> {
        v.as_u64().ok_or_else(|| format!("expected a whole number, found {}", describe(v)))
    }
    fn show(&self) -> String {
        self.to_string()
    }
}

/// A count, or null for the method's own choice (`auto` in labels).
impl KnobValue for Option<u32> {
    fn read(v: &Value) -> Result<Self, String> {
        match v {
            Value::Null => Ok(None),
            v => u32::read(v).map(Some).map_err(|e| format!("{e} (or null for the default)")),
        }
    }
    fn show(&self) -> String {
        self.map_or("auto".into(), |x| x.to_string())
    }
}

/// A count, `"device"` (Cycles' rule), or null for the default (`auto` in labels).
impl KnobValue for Option<PoolSize> {
    fn read(v: &Value) -> Result<Self, String> {
        match v {
            Value::Null => Ok(None),
            Value::String(s) if s == "device" => Ok(Some(PoolSize::Device)),
            v => u32::read(v)
                .map(|n| Some(PoolSize::Paths(n)))
                .map_err(|e| format!("{e} (or \"device\", or null for the default)")),
        }
    }
    fn show(&self) -> String {
        self.map_or("auto".into(), |x| x.to_string())
    }
}

impl KnobValue for f64 {
    fn read(v: &Value) -> Result<Self, String> {
        v.as_f64().ok_or_else(|| format!("expected a number, found {}", describe(v)))
    }
    fn show(&self) -> String {
        self.to_string()
    }
}

impl KnobValue for RayOffset {
    fn read(v: &Value) -> Result<Self, String> {
        RayOffset::parse(v.as_str().ok_or_else(|| format!("expected a string, found {}", describe(v)))?)
    }
    fn show(&self) -> String {
        self.name()
    }
}

/// `knob!(name, label, methods, Type, o => o.field.path)`: a knob held by one field.
macro_rules! knob {
    ($name:literal, $label:literal, $methods:expr, $t:ty, $o:ident => $($field:tt)+) => {
        Knob {
            name: $name,
            label: $label,
            methods: $methods,
            set: |$o, v| {
                $($field)+ = <$t as KnobValue>::read(v)?;
                Ok(())
            },
            get: |$o, _| serde_json::to_value(&$($field)+).unwrap_or(Value::Null),
            show: |$o, _| KnobValue::show(&$($field)+),
        }
    };
}

/// `shared!(name, label, Type, field)`: a knob of both GPU methods, set on both; each reports
/// its own.
macro_rules! shared {
    ($name:literal, $label:literal, $t:ty, $field:ident) => {
        Knob {
            name: $name,
            label: $label,
            methods: GPU,
            set: |o, v| {
                let x = <$t as KnobValue>::read(v)?;
                o.megakernel.$field = x;
                o.wavefront.$field = x;
                Ok(())
            },
            get: |o, m| {
                serde_json::to_value(per_method(m, o.megakernel.$field, o.wavefront.$field))
                    .unwrap_or(Value::Null)
            },
            show: |o, m| per_method(m, o.megakernel.$field, o.wavefront.$field).show(),
        }
    };
}

const ALL: &[Method] = &[Method::Cpu, Method::CpuF64, Method::Megakernel, Method::Wavefront];
const GPU: &[Method] = &[Method::Megakernel, Method::Wavefront];
const MEGAKERNEL: &[Method] = &[Method::Megakernel];
const WAVEFRONT: &[Method] = &[Method::Wavefront];

/// Every knob, in the order a config's sweeps expand (and variant labels list them).
pub static KNOBS: &[Knob] = &[
    knob!("light_sampling", "light-sampling", ALL, LightSampling, o => o.lights.sampling),
    knob!("light_select", "light-select", ALL, LightSelect, o => o.lights.select),
    shared!("workgroup_size", "wg", u32, workgroup_size),
    knob!("samples_per_dispatch", "spd", MEGAKERNEL, u64, o => o.megakernel.samples_per_dispatch),
    knob!("threads", "threads", MEGAKERNEL, Option<u32>, o => o.megakernel.threads),
    knob!("pool_size", "pool", WAVEFRONT, Option<PoolSize>, o => o.wavefront.pool_size),
    knob!("compaction", "compaction", WAVEFRONT, Compaction, o => o.wavefront.compaction),
    knob!("shade", "shade", WAVEFRONT, ShadePasses, o => o.wavefront.shade),
    shared!("schedule", "schedule", Schedule, schedule),
    knob!("sync_every", "sync", WAVEFRONT, u32, o => o.wavefront.sync_every),
    knob!("batches_in_flight", "in_flight", WAVEFRONT, u32, o => o.wavefront.batches_in_flight),
    knob!("tail", "tail", WAVEFRONT, Tail, o => o.wavefront.tail),
    knob!("tail_threshold", "tail-threshold", WAVEFRONT, f64, o => o.wavefront.tail_threshold),
    knob!("chunk_pools", "chunk-pools", WAVEFRONT, u32, o => o.wavefront.chunk_pools),
    knob!("scan", "scan", WAVEFRONT, Scan, o => o.wavefront.scan),
    knob!("append", "append", WAVEFRONT, Append, o => o.wavefront.append),
    knob!("queue_order", "queue-order", WAVEFRONT, QueueOrder, o => o.wavefront.queue_order),
    knob!("refill_below", "refill-below", WAVEFRONT, f64, o => o.wavefront.refill_below),
    knob!("compact_states", "compact-states", WAVEFRONT, CompactStates, o => o.wavefront.compact_states),
    knob!("ray_sort", "ray-sort", WAVEFRONT, RaySort, o => o.wavefront.ray_sort),
    knob!("compute_passes", "compute-passes", WAVEFRONT, ComputePasses, o => o.wavefront.compute_passes),
    knob!("launch", "launch", WAVEFRONT, Launch, o => o.wavefront.launch),
    knob!("shadow_rays", "shadow-rays", WAVEFRONT, ShadowRays, o => o.wavefront.shadow_rays),
    knob!("refill", "refill", WAVEFRONT, Refill, o => o.wavefront.refill),
    knob!("shader_checks", "shader-checks", GPU, ShaderChecks, o => o.shader_checks),
    knob!("specialize", "specialize", GPU, Specialize, o => o.specialize),
    knob!("timing", "timing", GPU, Timing, o => o.timing),
    knob!("ray_offset", "ray-offset", ALL, RayOffset, o => o.numerics.ray_offset),
    knob!("sphere_hit", "sphere-hit", ALL, SphereHit, o => o.numerics.sphere_hit),
    knob!("fresnel", "fresnel", ALL, Fresnel, o => o.numerics.fresnel),
    knob!("render_space", "render-space", ALL, RenderSpace, o => o.numerics.render_space),
    knob!("bvh", "bvh", ALL, BvhLayout, o => o.bvh),
    knob!("collapse", "collapse", ALL, Collapse, o => o.collapse),
    knob!("stack", "stack", GPU, BvhStack, o => o.stack),
    // The stress transforms: checked as they are read (a scale or translation f32 cannot hold).
    Knob {
        name: "scale",
        label: "scale",
        methods: ALL,
        set: |o, v| {
            let scale = v
                .as_f64()
                .ok_or_else(|| format!("expected a number > 0 (the scale factor), found {}", describe(v)))?;
            StressTransform { scale, ..Default::default() }.validate()?;
            o.stress.scale = scale;
            Ok(())
        },
        get: |o, _| serde_json::to_value(o.stress.scale).unwrap_or(Value::Null),
        show: |o, _| compact(o.stress.scale),
    },
    Knob {
        name: "translate",
        label: "translate",
        methods: ALL,
        set: |o, v| {
            o.stress.translate = translation(v)?;
            Ok(())
        },
        get: |o, _| serde_json::to_value(o.stress.translate).unwrap_or(Value::Null),
        show: |o, _| translate_name(o.stress.translate),
    },
];

/// runs.csv's knob columns, in the order they were added (a knob a later build adds goes at the
/// end, so existing columns keep their places). The same knobs as [`KNOBS`] (a test checks).
pub const COLUMNS: &[&str] = &[
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
    "launch",
    "shadow_rays",
    "refill",
    "bvh",
    "collapse",
    "stack",
];

/// The knob named `name`.
pub fn by_name(name: &str) -> Option<&'static Knob> {
    KNOBS.iter().find(|k| k.name == name)
}

/// The knobs `method` takes, in [`KNOBS`]' order.
pub fn of(method: Method) -> impl Iterator<Item = &'static Knob> {
    KNOBS.iter().filter(move |k| k.applies_to(method))
}

/// The knobs `method` takes, with their values in `o`, as reports record them.
pub fn view(method: Method, o: &MethodOptions) -> Value {
    Value::Object(of(method).map(|k| (k.name.to_owned(), k.get(o, method))).collect())
}

fn per_method<T>(m: Method, megakernel: T, wavefront: T) -> T {
    if m == Method::Wavefront {
        wavefront
    } else {
        megakernel
    }
}

/// What `translate` takes, for its errors.
const TRANSLATE_FORMS: &str = "expected a number D (the translation (D, D, D)) or an array [x, y, z]; \
a list of these is a sweep, except that an array of exactly three numbers is one vector [x, y, z] \
(sweep three distances as [[a], [b], [c]])";

/// One translation: a number D for (D, D, D), `[D]` likewise, or `[x, y, z]`.
fn translation(v: &Value) -> Result<[f64; 3], String> {
    let number = |v: &Value| v.as_f64().ok_or_else(|| TRANSLATE_FORMS.to_owned());
    let translate = match v {
        Value::Number(_) => [number(v)?; 3],
        Value::Array(a) if a.len() == 1 => [number(&a[0])?; 3],
        Value::Array(a) if a.len() == 3 => [number(&a[0])?, number(&a[1])?, number(&a[2])?],
        _ => return Err(format!("{TRANSLATE_FORMS}; found {}", describe(v))),
    };
    StressTransform { translate, ..Default::default() }.validate()?;
    Ok(translate)
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

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::BTreeSet;

    #[test]
    fn the_columns_are_the_knobs() {
        let columns: BTreeSet<&str> = COLUMNS.iter().copied().collect();
        let knobs: BTreeSet<&str> = KNOBS.iter().map(|k| k.name).collect();
        assert_eq!(columns, knobs);
        assert_eq!(columns.len(), COLUMNS.len(), "a column listed twice");
    }

    /// Reports spell an enum knob with serde, configs and the command line with clap: one
    /// spelling only if they agree, value by value.
    #[test]
    fn serde_and_clap_spell_every_value_alike() {
        fn same<T: clap::ValueEnum + serde::Serialize>() {
            for v in T::value_variants() {
                assert_eq!(serde_json::to_value(v).unwrap(), Value::String(Named::name(v)));
            }
        }
        same::<Compaction>();
        same::<ShadePasses>();
        same::<Schedule>();
        same::<Tail>();
        same::<Scan>();
        same::<Append>();
        same::<QueueOrder>();
        same::<CompactStates>();
        same::<RaySort>();
        same::<ComputePasses>();
        same::<ShaderChecks>();
        same::<Specialize>();
        same::<Timing>();
        same::<LightSampling>();
        same::<LightSelect>();
        same::<SphereHit>();
        same::<Fresnel>();
        same::<RenderSpace>();
        same::<BvhLayout>();
        same::<Collapse>();
        same::<BvhStack>();
        same::<Method>();
    }

    /// Each knob reads back what it records, and its label shows the value.
    #[test]
    fn every_knob_reads_what_it_records() {
        for k in KNOBS {
            let m = k.methods[k.methods.len() - 1];
            let o = MethodOptions::default();
            let recorded = k.get(&o, m);
            let mut again = MethodOptions::default();
            k.set(&mut again, &recorded).unwrap_or_else(|e| panic!("{}: {e}", k.name));
            assert_eq!(k.get(&again, m), recorded, "{}", k.name);
            assert!(k.label(&o, m).starts_with(&format!("{}=", k.label)));
        }
        let e =
            by_name("compaction").unwrap().set(&mut MethodOptions::default(), &"scna".into()).unwrap_err();
        assert_eq!(
            e,
            "unknown value \"scna\" (did you mean \"scan\"?); expected \"off\", \"atomic\" or \"scan\""
        );
    }
}
