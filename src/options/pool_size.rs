//! `--pool-size`: the wavefront's paths in flight, a count or `device` (Cycles' rule for the
//! device's multiprocessors, `gpu::wavefront::pool`). Configs and reports spell a count as a
//! number and the rule as the string "device"; a report records the count that ran.

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
