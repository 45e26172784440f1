//! Every method knob an experiment config can set, in one table ([`KNOBS`], each wavefront
//! knob's row stated in its module, `wavefront/<knob>.rs`), and runs.csv's columns
//! ([`COLUMNS`]). Configs read knobs through it, reports write them through it, and variant
//! labels are made by it.

pub use super::knob::Knob;
use super::knob::{knob, KnobValue, ALL, GPU, MEGAKERNEL};
use super::wavefront::{
    append, batches_in_flight, chunk_pools, compact_states, compaction, compute_passes, launch, pool_size,
    queue_order, ray_sort, refill, refill_below, scan, shade, shadow_rays, sync_every, tail, tail_threshold,
};
use super::{Method, MethodOptions, Schedule, ShaderChecks, Specialize, Timing};
use crate::bvh::collapse::Collapse;
use crate::bvh::stack::BvhStack;
use crate::bvh::BvhLayout;
use crate::light_options::{LightSampling, LightSelect};
use crate::numerics::{Fresnel, RayOffset, SphereHit};
use crate::render_space::RenderSpace;
use crate::scene::stress::StressTransform;
use crate::strict_json::describe;
use serde_json::Value;

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
            spelled_alike: <$t as KnobValue>::spelled_alike,
        }
    };
}

/// Every knob, in the order a config's sweeps expand (and variant labels list them).
pub static KNOBS: &[Knob] = &[
    knob!("light_sampling", "light-sampling", ALL, LightSampling, o => o.lights.sampling),
    knob!("light_select", "light-select", ALL, LightSelect, o => o.lights.select),
    shared!("workgroup_size", "wg", u32, workgroup_size),
    knob!("samples_per_dispatch", "spd", MEGAKERNEL, u64, o => o.megakernel.samples_per_dispatch),
    knob!("threads", "threads", MEGAKERNEL, Option<u32>, o => o.megakernel.threads),
    pool_size::KNOB,
    compaction::KNOB,
    shade::KNOB,
    shared!("schedule", "schedule", Schedule, schedule),
    sync_every::KNOB,
    batches_in_flight::KNOB,
    tail::KNOB,
    tail_threshold::KNOB,
    chunk_pools::KNOB,
    scan::KNOB,
    append::KNOB,
    queue_order::KNOB,
    refill_below::KNOB,
    compact_states::KNOB,
    ray_sort::KNOB,
    compute_passes::KNOB,
    launch::KNOB,
    shadow_rays::KNOB,
    refill::KNOB,
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
        spelled_alike: || true,
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
        spelled_alike: || true,
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
        for k in KNOBS {
            assert!(k.spelled_alike(), "{}", k.name);
        }
        for v in <Method as clap::ValueEnum>::value_variants() {
            assert_eq!(serde_json::to_value(v).unwrap(), Value::String(super::super::Named::name(v)));
        }
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
