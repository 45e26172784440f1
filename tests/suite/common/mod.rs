//! Shared test set-up: a few GPU contexts shared by the tests, and the CI rule that GPU tests are
//! never skipped silently.
#![allow(dead_code)]

use std::sync::OnceLock;
use wavetrace::film::Film;
use wavetrace::gpu::GpuContext;
use wavetrace::stats::z_test;

/// The most GPU contexts (devices) the tests open at once. Tests running at the same time each
/// get a context of their own while there are fewer than this: one device's queue runs its
/// submissions one after another, and on the software driver a render's small dispatches leave
/// cores idle that another test's queue can use. But each device creates its own pipelines, and
/// on lavapipe with a cold shader cache that is about half of the suite, paid again per device.
/// The suite on 2 cores, four test threads, cold cache: one device 429 s (314 s of pipeline
/// creation, 162% CPU), two 361 s (354 s), four 396 s (487 s).
const MAX_CONTEXTS: usize = 2;

struct Slot {
    ctx: OnceLock<Option<GpuContext>>,
    /// Test threads holding this context now.
    users: std::sync::atomic::AtomicUsize,
}

static SLOTS: [Slot; MAX_CONTEXTS] =
    [const { Slot { ctx: OnceLock::new(), users: std::sync::atomic::AtomicUsize::new(0) } }; MAX_CONTEXTS];

/// A test thread's context (libtest runs each test on a thread of its own): the slot with the
/// fewest users when the test first asks, given back when the thread ends.
struct Lease(usize);

impl Lease {
    fn take() -> Lease {
        use std::sync::atomic::Ordering::SeqCst;
        static PICK: std::sync::Mutex<()> = std::sync::Mutex::new(());
        let _one_at_a_time = PICK.lock().unwrap_or_else(|e| e.into_inner());
        let k = (0..MAX_CONTEXTS).min_by_key(|&k| SLOTS[k].users.load(SeqCst)).expect("slots");
        SLOTS[k].users.fetch_add(1, SeqCst);
        Lease(k)
    }
}

impl Drop for Lease {
    fn drop(&mut self) {
        SLOTS[self.0].users.fetch_sub(1, std::sync::atomic::Ordering::SeqCst);
    }
}

thread_local! {
    static LEASE: Lease = Lease::take();
}

/// The GPU, or `None` on a machine without one — except where `WAVETRACE_REQUIRE_GPU` or `CI`
/// is set, where a missing adapter fails the test instead of skipping it. The same context for
/// the whole of a test (on its thread).
pub fn gpu() -> Option<&'static GpuContext> {
    let k = LEASE.with(|l| l.0);
    SLOTS[k]
        .ctx
        .get_or_init(|| match GpuContext::new(std::env::var("WAVETRACE_ADAPTER").ok().as_deref()) {
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

/// The wavefront's render of built-in `scene` with knobs `wf`, instrumented or not.
pub fn render_wavefront(
    scene: &str,
    s: &wavetrace::settings::RenderSettings,
    wf: wavetrace::gpu::wavefront::WavefrontOptions,
    instrument: bool,
) -> anyhow::Result<wavetrace::method::RenderOutput> {
    use wavetrace::method::{render, Method, MethodOptions};
    let scene = wavetrace::scene::builtin::by_name(scene).unwrap();
    let opts = MethodOptions { wavefront: wf, instrument, ..Default::default() };
    render(Method::Wavefront, &scene, s, &opts, gpu(), &|_| {})
}

/// A film rendered with the megakernel tail against one without: the same paths (every pixel's
/// samples, invalid samples and rays equal), radiance equal up to rounding. The tail runs a
/// path's last bounces in another shader than the wavefront's shade passes; the arithmetic is
/// the same WGSL, but a driver may fuse multiply-adds differently in each (WGSL allows it), and
/// on an H200 one sample of 7,680 differed in its last bit (Cornell box, NEE). 1e-6 of a sum is
/// eight f32 ulps of its largest sample; a path that went another way changes far more.
#[track_caller]
pub fn assert_same_paths(what: &str, a: &Film, b: &Film) {
    assert_eq!((a.width, a.height, a.spp), (b.width, b.height, b.spp), "{what}: film size");
    for (i, (p, q)) in a.pixels.iter().zip(&b.pixels).enumerate() {
        assert_eq!((p.count, p.invalid, p.rays), (q.count, q.invalid, q.rays), "{what}: pixel {i}");
        for (x, y) in p.sum.iter().zip(&q.sum).chain(p.sum_sq.iter().zip(&q.sum_sq)) {
            assert!((x - y).abs() <= 1e-6 * x.abs().max(y.abs()), "{what}: pixel {i}: {p:?} vs {q:?}");
        }
    }
}

/// A film against the waves' film of the same job: bit for bit, or with the megakernel tail
/// (another shader) the same paths, radiance up to rounding ([`assert_same_paths`]).
#[track_caller]
pub fn assert_waves_film(what: &str, film: &Film, waves: &Film, tail: wavetrace::gpu::wavefront::Tail) {
    if tail == wavetrace::gpu::wavefront::Tail::Megakernel {
        assert_same_paths(what, film, waves);
    } else {
        assert_eq!(film, waves, "{what}");
    }
}

/// Ray-count tolerance between two f32 renderers tracing the same paths (the CPU reference and a
/// GPU method): they part only where rounding sends a path another way. Within 1e-3 on llvmpipe;
/// NVIDIA's compiler fuses multiply-adds (WGSL allows it) and rounds division and square roots
/// its own way, and on an H200 the Cornell box differed by 1.7e-3 (40x40 at 64 spp, no NEE) and
/// 1.1e-3 (NEE). A path that took other random numbers would change far more than this.
pub const F32_RAY_TOLERANCE: f64 = 3e-3;

/// Two methods tracing the same paths agree (DESIGN.md §4): ≥ 99% of pixels pass a z-test at
/// α = 0.01 and image means are within 1%; their ray counts (rays/s in reports) agree up to the
/// paths that rounding sends another way, within `ray_tolerance` (relative).
#[track_caller]
pub fn assert_agree_rays(name: &str, a: &Film, b: &Film, ray_tolerance: f64) {
    let t = z_test(a, b, 0.01);
    eprintln!("{name}: {:.4} of pixels pass, means differ by {:.2e}", t.pass_fraction, t.mean_rel_diff);
    assert!(t.pass_fraction >= 0.99, "{name}: only {:.4} of pixels pass ({t:?})", t.pass_fraction);
    assert!(t.mean_rel_diff <= 0.01, "{name}: image means differ by {:.4}", t.mean_rel_diff);
    let (ra, rb) = (a.rays() as f64, b.rays() as f64);
    assert!(ra >= (a.spp as usize * a.pixels.len()) as f64, "{name}: at least one ray per sample");
    assert!((ra - rb).abs() <= ray_tolerance * rb, "{name}: {ra} vs {rb} rays traced");
}

/// The repository the tests read (scenes, configs, committed results): the checkout they were
/// built in, or `WAVETRACE_TEST_ROOT` where the test binary travelled without it (the device
/// run, scripts/device_figures.sh, carries the built suite to a GPU machine's copy of the tree).
pub fn root() -> std::path::PathBuf {
    std::env::var_os("WAVETRACE_TEST_ROOT").map_or_else(|| env!("CARGO_MANIFEST_DIR").into(), Into::into)
}

/// The `wavetrace` binary the command-line tests run: the one cargo built beside the tests, or
/// `WAVETRACE_TEST_BIN` where the test binary travelled without it (the device run).
pub fn bin() -> std::path::PathBuf {
    std::env::var_os("WAVETRACE_TEST_BIN").map_or_else(|| env!("CARGO_BIN_EXE_wavetrace").into(), Into::into)
}

/// Scratch space for files the tests write: cargo's per-target temporary directory, or
/// `WAVETRACE_TEST_TMP` where the test binary travelled without its target directory.
pub fn tmp() -> std::path::PathBuf {
    std::env::var_os("WAVETRACE_TEST_TMP").map_or_else(|| env!("CARGO_TARGET_TMPDIR").into(), Into::into)
}

/// A check this adapter cannot run (it lacks a feature, or the check is about another driver):
/// never a silent pass. Prints `SKIPPED: <check>: <why>` and appends the line to
/// `skipped-checks.txt` in the test scratch directory, which scripts/test.sh prints after the
/// run (cargo captures a passing test's output). `WAVETRACE_FORBID_SKIPS` makes it a failure.
pub fn skipped(check: &str, why: &str) {
    use std::io::Write;
    let line = format!("SKIPPED: {check}: {why}");
    eprintln!("{line}");
    assert!(std::env::var_os("WAVETRACE_FORBID_SKIPS").is_none(), "{line} (WAVETRACE_FORBID_SKIPS is set)");
    let path = tmp().join(SKIPPED_FILE);
    if let Ok(mut f) = std::fs::OpenOptions::new().create(true).append(true).open(&path) {
        let _ = writeln!(f, "{line}");
    }
}

/// The Python with third-party checkers (the OpenEXR bindings, `jsonschema`) that scripts/test.sh
/// makes with scripts/exr_reader.sh and exports as `WAVETRACE_EXR_PYTHON`; without it `check` is
/// listed as [`skipped`].
pub fn third_party_python(check: &str) -> Option<std::path::PathBuf> {
    let py = std::env::var_os("WAVETRACE_EXR_PYTHON").map(std::path::PathBuf::from);
    if py.is_none() {
        skipped(
            check,
            "WAVETRACE_EXR_PYTHON is not set (scripts/test.sh sets it with scripts/exr_reader.sh)",
        );
    }
    py
}

/// Where [`skipped`] lists the checks a run skipped (under [`tmp`]).
pub const SKIPPED_FILE: &str = "skipped-checks.txt";

/// Same-sample agreement of two films: the fraction of pixels whose three channel means agree
/// within 1e-3 relative (relative to the larger, floored at `floor` near black), and the images'
/// relative mean difference. The bar for methods that trace the same paths (wavefront.rs,
/// paired.rs).
pub fn same_sample_agreement(a: &wavetrace::film::Film, b: &wavetrace::film::Film, floor: f64) -> (f64, f64) {
    assert_eq!((a.width, a.height, a.spp), (b.width, b.height, b.spp));
    let close = a
        .pixels
        .iter()
        .zip(&b.pixels)
        .filter(|(p, q)| {
            let (m, n) = (p.mean(), q.mean());
            (0..3).all(|c| (m[c] - n[c]).abs() <= 1e-3 * m[c].abs().max(n[c].abs()).max(floor))
        })
        .count();
    let frac = close as f64 / a.pixels.len() as f64;
    (frac, (a.image_mean() - b.image_mean()).abs() / b.image_mean())
}

/// Both megakernels, waves and regenerate + tail, every other option at its default: the four
/// ways the GPU traces a path, for tests that a knob changes no film in any of them.
pub fn gpu_ways() -> Vec<(wavetrace::method::Method, wavetrace::method::MethodOptions)> {
    use wavetrace::gpu::megakernel::MegakernelOptions;
    use wavetrace::gpu::wavefront::{Schedule, Tail, WavefrontOptions};
    use wavetrace::method::{Method, MethodOptions};
    let waves = WavefrontOptions { schedule: Schedule::Waves, ..Default::default() };
    vec![
        (Method::Megakernel, MethodOptions::default()),
        (
            Method::Megakernel,
            MethodOptions {
                megakernel: MegakernelOptions { schedule: Schedule::Regenerate, ..Default::default() },
                ..Default::default()
            },
        ),
        (Method::Wavefront, MethodOptions { wavefront: waves, ..Default::default() }),
        (
            Method::Wavefront,
            MethodOptions {
                wavefront: WavefrontOptions {
                    schedule: Schedule::Regenerate,
                    tail: Tail::Megakernel,
                    ..waves
                },
                ..Default::default()
            },
        ),
    ]
}
