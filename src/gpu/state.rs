//! The GPU's clocks, temperature, power and throttle reasons, read through NVML on NVIDIA
//! (`nvml-wrapper`, which loads `libnvidia-ml.so.1` at run time): what moves under a
//! benchmark, recorded before and after each run's timed renders so a report shows the state
//! its timings were taken in. Reading only: nothing here changes a setting. Where NVML is absent
//! (no NVIDIA driver, another vendor, the software driver) nothing is read and nothing fails.

use nvml_wrapper::enum_wrappers::device::{Clock, TemperatureSensor};
use nvml_wrapper::Nvml;
use serde::{Deserialize, Serialize};

use crate::gpu::context::AdapterSummary;

/// One reading. Each field is None where the device does not report it.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct GpuState {
    /// Streaming-multiprocessor clock, MHz.
    pub sm_clock_mhz: Option<u32>,
    pub memory_clock_mhz: Option<u32>,
    /// GPU die, °C.
    pub temperature_c: Option<u32>,
    /// Board power draw, W.
    pub power_watts: Option<f64>,
    /// Why the clocks are held below their maximum (NVML's names, e.g. `SW_POWER_CAP`,
    /// `HW_SLOWDOWN`, `GPU_IDLE`); empty when nothing holds them.
    pub throttle_reasons: Option<Vec<String>>,
}

/// The state before a run's first timed render and after its last.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct GpuStateSpan {
    pub before: GpuState,
    pub after: GpuState,
}

/// NVML opened on the device an adapter names.
pub struct GpuMonitor {
    nvml: Nvml,
    index: u32,
    /// NVML's name for the device, for the report.
    pub name: String,
}

impl std::fmt::Debug for GpuMonitor {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("GpuMonitor").field("index", &self.index).field("name", &self.name).finish()
    }
}

/// PCI vendor id of NVIDIA.
const NVIDIA: u32 = 0x10de;

impl GpuMonitor {
    /// NVML's device for `adapter`: matched by PCI bus id where wgpu reports one, else the only
    /// device, else the one whose name is the adapter's. None off NVIDIA, without NVML, or when
    /// no device matches.
    pub fn open(adapter: &AdapterSummary) -> Option<Self> {
        if adapter.vendor != NVIDIA {
            return None;
        }
        let nvml = match Nvml::init() {
            Ok(n) => n,
            Err(e) => {
                log::info!("GPU state not recorded: NVML unavailable ({e})");
                return None;
            }
        };
        let count = nvml.device_count().ok()?;
        let wanted = parse_bus_id(&adapter.pci_bus_id);
        let mut by_name = None;
        for index in 0..count {
            let Ok(device) = nvml.device_by_index(index) else { continue };
            let name = device.name().unwrap_or_default();
            let bus = device.pci_info().ok().and_then(|p| parse_bus_id(&p.bus_id));
            if wanted.is_some() && bus == wanted {
                return Some(Self { nvml, index, name });
            }
            if by_name.is_none() && (count == 1 || name == adapter.name) {
                by_name = Some((index, name));
            }
        }
        let (index, name) = by_name?;
        Some(Self { nvml, index, name })
    }

    /// A reading now; fields the device does not report stay None.
    pub fn sample(&self) -> GpuState {
        let Ok(d) = self.nvml.device_by_index(self.index) else { return GpuState::default() };
        GpuState {
            sm_clock_mhz: d.clock_info(Clock::SM).ok(),
            memory_clock_mhz: d.clock_info(Clock::Memory).ok(),
            temperature_c: d.temperature(TemperatureSensor::Gpu).ok(),
            power_watts: d.power_usage().ok().map(|mw| f64::from(mw) / 1000.0),
            throttle_reasons: d
                .current_throttle_reasons()
                .ok()
                .map(|r| r.iter_names().map(|(name, _)| name.to_string()).collect()),
        }
    }
}

/// A device's streaming multiprocessors: how many, and the threads each holds at once.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Multiprocessors {
    pub count: u32,
    pub threads_each: u32,
}

impl GpuMonitor {
    /// The device's multiprocessors: NVML's count where it gives one (MIG instances), else its
    /// CUDA cores over the cores per SM of its compute capability; None for an architecture
    /// [`sm_shape`] does not know.
    pub fn multiprocessors(&self) -> Option<Multiprocessors> {
        let d = self.nvml.device_by_index(self.index).ok()?;
        let cc = d.cuda_compute_capability().ok()?;
        let (cores_each, threads_each) = sm_shape(cc.major, cc.minor)?;
        let count = match d.attributes() {
            Ok(a) if a.multiprocessor_count > 0 => a.multiprocessor_count,
            _ => d.num_cores().ok()? / cores_each,
        };
        (count > 0).then_some(Multiprocessors { count, threads_each })
    }
}

/// (FP32 cores per SM, most resident threads per SM) of a CUDA compute capability, from the
/// CUDA C++ Programming Guide's tables; None for one not listed.
pub fn sm_shape(major: i32, minor: i32) -> Option<(u32, u32)> {
    Some(match (major, minor) {
        (5, _) => (128, 2048),
        (6, 0) => (64, 2048),
        (6, _) => (128, 2048),
        (7, 5) => (64, 1024),
        (7, _) => (64, 2048),
        (8, 0) => (64, 2048),
        (8, 7) => (128, 2048),
        (8, _) => (128, 1536),
        (9, 0) => (128, 2048),
        (10, _) => (128, 2048),
        (12, _) => (128, 1536),
        _ => return None,
    })
}

/// A PCI bus id as (domain, bus, device, function), from wgpu's `0000:65:00.0` or NVML's
/// `00000000:65:00.0`; None when empty or malformed.
pub fn parse_bus_id(id: &str) -> Option<(u32, u32, u32, u32)> {
    let (domain, rest) = id.trim().split_once(':')?;
    let (bus, rest) = rest.split_once(':')?;
    let (device, function) = rest.split_once('.')?;
    let hex = |s: &str| u32::from_str_radix(s.trim_end_matches('\0'), 16).ok();
    Some((hex(domain)?, hex(bus)?, hex(device)?, hex(function)?))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bus_ids_match_across_spellings() {
        assert_eq!(parse_bus_id("0000:65:00.0"), Some((0, 0x65, 0, 0)));
        assert_eq!(parse_bus_id("00000000:65:00.0"), parse_bus_id("0000:65:00.0"));
        assert_eq!(parse_bus_id(""), None);
        assert_eq!(parse_bus_id("not a bus"), None);
    }

    #[test]
    fn hopper_has_132_sms_of_2048_threads() {
        // An H100 SXM or H200: 16,896 CUDA cores at compute capability 9.0.
        let (cores, threads) = sm_shape(9, 0).unwrap();
        assert_eq!((16_896 / cores, threads), (132, 2048));
        // An A100: 6,912 cores at 8.0 (108 SMs); an RTX 4090: 16,384 at 8.9 (128 SMs).
        assert_eq!(6_912 / sm_shape(8, 0).unwrap().0, 108);
        assert_eq!(sm_shape(8, 9), Some((128, 1536)));
        assert_eq!(sm_shape(3, 5), None);
    }
}
