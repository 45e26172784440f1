//! wavetrace: a research testbed comparing megakernel and wavefront GPU path tracing.
//!
//! The CPU reference ([`cpu`]) is the ground truth; the GPU methods ([`gpu`]) run on wgpu.
//! All of them draw random numbers from [`rng`], so they trace the same paths.

pub mod arithmetic_range;
pub mod bvh;
pub mod camera;
pub mod cancel;
pub mod chart;
pub mod cli;
pub mod cpu;
pub mod experiment;
pub mod film;
pub mod gpu;
pub mod image_io;
pub mod input_error;
pub mod layout;
pub mod light_options;
pub mod light_table;
pub mod measure;
pub mod method;
pub mod metrics;
pub mod numerics;
pub mod options;
pub mod packed_scene;
pub mod primitive_area;
pub mod progress;
pub mod real;
pub mod render_job;
pub mod render_space;
pub mod replay;
pub mod report;
pub mod rng;
pub mod scene;
pub mod settings;
pub mod shader_include;
pub mod stats;
pub mod strict_json;
pub mod vec3;
pub mod warmup;
