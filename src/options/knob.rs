//! What a knob is to configs and reports: its name (the config's key, the report's and
//! runs.csv's column), the methods that take it, its label in variant names, and how its value
//! is read from a config, recorded and shown. Each wavefront knob states its own row in its
//! module (`wavefront/<knob>.rs`); `knobs.rs` lists them all.

use super::{Method, MethodOptions, Named, ShaderChecks, Specialize, Timing};
use crate::bvh::collapse::Collapse;
use crate::bvh::stack::BvhStack;
use crate::bvh::BvhLayout;
use crate::light_options::{LightSampling, LightSelect};
use crate::numerics::{Fresnel, RayOffset, SphereHit};
use crate::render_space::RenderSpace;
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
    pub(super) set: fn(&mut MethodOptions, &Value) -> Result<(), String>,
    /// The value as reports record it, for a method.
    pub(super) get: fn(&MethodOptions, Method) -> Value,
    /// The value as labels show it, for a method.
    pub(super) show: fn(&MethodOptions, Method) -> String,
    pub(super) spelled_alike: fn() -> bool,
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

    /// Whether reports (serde) and configs (clap) spell every value of its type alike.
    pub fn spelled_alike(&self) -> bool {
        (self.spelled_alike)()
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
pub(super) trait KnobValue: Sized + serde::Serialize {
    fn read(v: &Value) -> Result<Self, String>;
    fn show(&self) -> String;
    /// Whether serde and clap spell each value alike (an enum's every variant; `true` for the rest).
    fn spelled_alike() -> bool {
        true
    }
}

/// `enum_values!(Type, ...)`: option enums as knob values, spelled by their clap `ValueEnum`.
macro_rules! enum_values {
    ($($t:ty),*) => {$(
        impl $crate::options::knob::KnobValue for $t {
            fn read(v: &serde_json::Value) -> Result<Self, String> {
                $crate::options::knob::read_enum(v)
            }
            fn show(&self) -> String {
                $crate::options::Named::name(self)
            }
            fn spelled_alike() -> bool {
                use clap::ValueEnum;
                Self::value_variants().iter().all(|v| {
                    serde_json::to_value(v).ok() == Some(serde_json::Value::String($crate::options::Named::name(v)))
                })
            }
        }
    )*};
}
pub(super) use enum_values;

/// One value of an option enum, by its clap name, or the reason it is none.
pub(super) fn read_enum<T: clap::ValueEnum>(v: &Value) -> Result<T, String> {
    let names: Vec<String> = T::value_variants().iter().map(|x| Named::name(x)).collect();
    let names: Vec<&str> = names.iter().map(String::as_str).collect();
    let s = v.as_str().ok_or_else(|| format!("expected a string, found {}", describe(v)))?;
    T::from_str(s, false).map_err(|_| {
        format!("unknown value {s:?}{}; expected {}", did_you_mean(s, &names), quoted_list(&names))
    })
}

enum_values!(
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
    BvhStack,
    super::Schedule
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
        $crate::options::knob::Knob {
            name: $name,
            label: $label,
            methods: $methods,
            set: |$o, v| {
                $($field)+ = <$t as $crate::options::knob::KnobValue>::read(v)?;
                Ok(())
            },
            get: |$o, _| serde_json::to_value(&$($field)+).unwrap_or(serde_json::Value::Null),
            show: |$o, _| $crate::options::knob::KnobValue::show(&$($field)+),
            spelled_alike: <$t as $crate::options::knob::KnobValue>::spelled_alike,
        }
    };
}
pub(super) use knob;

/// `flag! { /// help \n #[arg(...)] name: Type }`: a knob's command-line flag, as clap derives
/// it from the doc comment (its `--help` text) and the attribute. The options' struct flattens
/// each knob's `Flag` in its list's order (`wavefront/mod.rs`).
macro_rules! flag {
    ($(#[$m:meta])* $name:ident: $t:ty) => {
        #[derive(clap::Args)]
        #[group(skip)]
        pub struct Flag {
            $(#[$m])*
            pub $name: $t,
        }
    };
}
pub(super) use flag;

pub(super) const ALL: &[Method] = &[Method::Cpu, Method::CpuF64, Method::Megakernel, Method::Wavefront];
pub(super) const GPU: &[Method] = &[Method::Megakernel, Method::Wavefront];
pub(super) const MEGAKERNEL: &[Method] = &[Method::Megakernel];
pub(super) const WAVEFRONT: &[Method] = &[Method::Wavefront];
