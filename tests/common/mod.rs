//! Shared test set-up: one GPU context per test binary, and the CI rule that GPU tests are
//! never skipped silently.
#![allow(dead_code)]

use std::sync::OnceLock;
use wavetrace::gpu::GpuContext;

/// The GPU, or `None` on a machine without one — except where `WAVETRACE_REQUIRE_GPU` or `CI`
/// is set, where a missing adapter fails the test instead of skipping it.
pub fn gpu() -> Option<&'static GpuContext> {
    static CTX: OnceLock<Option<GpuContext>> = OnceLock::new();
    CTX.get_or_init(|| match GpuContext::new(std::env::var("WAVETRACE_ADAPTER").ok().as_deref()) {
        Ok(ctx) => Some(ctx),
        Err(e) => {
            let required =
                std::env::var_os("WAVETRACE_REQUIRE_GPU").is_some() || std::env::var_os("CI").is_some();
            assert!(!required, "GPU tests are required here but no adapter could be opened: {e}");
            eprintln!("SKIPPING GPU test: {e}");
            None
        }
    })
    .as_ref()
}
