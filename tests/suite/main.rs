//! The integration tests, as one test binary: each module below was its own crate, and linking
//! fifteen binaries against wgpu cost most of the test build's time. Modules share one GPU
//! context (`common::gpu`), so GPU tests open the adapter once per run.

mod common;

mod agreement;
mod bandwidth;
mod bvh_layouts;
mod chart;
mod cli;
mod cli_paths;
mod coherence;
mod dispatch_cost;
mod doc_commands;
mod docs;
mod edge_cases;
mod experiment;
mod exr_third_party;
mod film;
mod gltf;
mod gpu_rng;
mod image_io;
mod indirect_args;
mod intersect_cost;
mod layout;
mod lights;
mod megakernel;
mod metrics;
mod paired;
mod pass_graph;
mod ray_sort;
mod reference_cache;
mod refill;
mod render_space;
mod report_page;
mod repository;
mod resume;
mod roulette;
mod sampling;
mod scale;
mod scene_format;
mod schedule_rule;
mod simd_replay;
mod slurm;
mod specialize;
mod stability;
mod stage_cache;
mod steadiness;
mod tidy;
mod timing;
mod wavefront;
