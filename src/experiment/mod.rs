//! Experiments: a config names scenes, settings and methods; every combination is a run; the
//! runner renders them (timed repetitions after warm-ups), measures error against a reference and
//! writes `report.json` (with its tidy tables `runs.csv`, `passes.csv`), EXRs, PNG previews, charts
//! and a self-contained `report.html`.
//!
//! ```text
//! config.json ─► ExperimentConfig (validated whole) ─► plan: runs (scene × size × depth × spp × method)
//!   [--resume: keep the runs an earlier attempt in DIR finished (same config, build, shard)]
//!   for group in plan (a job's GPU variants together; each other run alone), less those kept:
//!       reference(scene, size)             cached on disk, keyed by scene text and settings
//!       warm-up, run by run                timed: until the GPU has worked and frames agree
//!       timed renders, taking turns        median, spread, interval; unstable/cold flags
//!       [instrumented render]              SIMD efficiency (separate: counters skew time)
//!       EXR, PNG, error map, metrics       MSE, relMSE, SMAPE, FLIP, 1/(relMSE·time)
//!       report.json, runs.csv, passes.csv  rewritten atomically after every group
//!   charts/*.svg, report.html              re-drawable from report.json (`experiment report`)
//! ```

pub mod baseline;
pub mod bvh_table;
pub mod cache_lock;
pub mod charts;
pub mod config;
pub mod error_map;
pub mod escape;
pub mod gpu_slot;
pub mod html;
pub mod markdown;
pub mod merge;
pub mod method_colours;
pub mod outputs;
pub mod overrides;
pub mod plan;
pub mod reference;
pub mod report;
pub mod resume;
pub mod runner;
pub mod simd_html;
pub mod stability;
pub mod tidy;
pub mod verdict;

pub use crate::input_error::InputError;
pub use config::{ExperimentConfig, CONFIG_SCHEMA};
pub use report::{ExperimentReport, REPORT_SCHEMA};
