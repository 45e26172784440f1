//! `--pool-size`: the wavefront's paths in flight, a count or `device` (Cycles' rule for the
//! device's multiprocessors, `gpu::wavefront::pool`). Configs and reports spell a count as a
//! number and the rule as the string "device"; a report records the count that ran.

use super::*;
use serde_json::Value;
use std::fmt;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PoolSize {
    /// This many paths (reduced with a notice where the adapter cannot hold them).
    Paths(u32),
    /// Sized to the device: max(SMs × threads per SM, 65536) × 16, as Cycles sizes its path
    /// states on CUDA; the default pool where the SM count is unknown (no NVML).
    Device,
}

impl PoolSize {
    /// The command line's and configs' spelling: a whole number, or `device`.
    pub fn parse(s: &str) -> Result<Self, String> {
        if s == "device" {
            return Ok(PoolSize::Device);
        }
        s.parse::<u32>()
            .map(PoolSize::Paths)
            .map_err(|_| format!("expected a whole number of paths or \"device\", found {s:?}"))
    }
}

impl fmt::Display for PoolSize {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            PoolSize::Paths(n) => write!(f, "{n}"),
            PoolSize::Device => f.write_str("device"),
        }
    }
}

impl serde::Serialize for PoolSize {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match self {
            PoolSize::Paths(n) => s.serialize_u32(*n),
            PoolSize::Device => s.serialize_str("device"),
        }
    }
}

flag! {
    /// Wavefront: paths in flight (default about a million, less where the adapter's storage
    /// bindings are smaller; a pool that does not fit is reduced with a notice), or `device`:
    /// Cycles' rule, max(SMs × threads per SM, 65536) × 16 (about 4.3 million on an H100 or
    /// H200; the SM count from NVIDIA's NVML, the default pool where it is unknown).
    #[arg(long, value_parser = PoolSize::parse, hide_short_help = true)]
    pool_size: Option<PoolSize>
}

pub const KNOB: Knob = knob!("pool_size", "pool", WAVEFRONT, Option<PoolSize>, o => o.wavefront.pool_size);

pub fn range(o: &WavefrontOptions) -> Result<(), OptionError> {
    if o.pool_size == Some(PoolSize::Paths(0)) {
        return Err(OptionError::range("pool_size", "must be at least 1".into()));
    }
    Ok(())
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spelled_as_a_count_or_device() {
        assert_eq!(PoolSize::parse("65536"), Ok(PoolSize::Paths(65536)));
        assert_eq!(PoolSize::parse("device"), Ok(PoolSize::Device));
        assert!(PoolSize::parse("Device").is_err());
        assert!(PoolSize::parse("-1").is_err());
        assert_eq!(serde_json::to_string(&PoolSize::Paths(7)).unwrap(), "7");
        assert_eq!(serde_json::to_string(&PoolSize::Device).unwrap(), "\"device\"");
        assert_eq!(PoolSize::Device.to_string(), "device");
    }
}
