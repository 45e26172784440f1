//! The regenerating wavefront decides after each check on the GPU (`schedule_decide`, with the
//! rule in `shaders/wavefront/shared/schedule_rule.wgsl`), while `schedule::Decision::after` stays the
//! documented rule the CPU replay follows. Over thousands of randomized ring states — consistent
//! ones, as a share can reach them — the WGSL rule decides exactly as the Rust one.

use crate::common;

use wavetrace::gpu::buffers::{read_back, storage_entry, storage_init, storage_zeroed};
use wavetrace::gpu::shaders;
use wavetrace::gpu::wavefront::schedule::{ChunkCounters, Decision, Ring};

/// Words per case in shaders/tests/schedule_probe.wgsl, and the most ring chunks a case holds.
const CASE_WORDS: usize = 32;
const MAX_RING: u32 = (CASE_WORDS - 9) as u32;

/// A small deterministic generator (xorshift), so a failure names a case that repeats.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }
    /// Uniform in lo..=hi.
    fn range(&mut self, lo: u32, hi: u32) -> u32 {
        lo + (self.next() % (hi as u64 - lo as u64 + 1)) as u32
    }
    fn chance(&mut self, percent: u32) -> bool {
        self.range(1, 100) <= percent
    }
}

struct Case {
    ring: Ring,
    pool: u32,
    oldest: u32,
    started_before: u32,
    counters: ChunkCounters,
    threshold: Option<f64>,
}

/// A state a share can be in at a check: the chunks before `oldest` in the film, samples started
/// up to the ring's end, each chunk in the ring with at most its started samples finished (often
/// all of them, so chunks complete), thresholds small and large.
fn random_case(g: &mut Rng) -> Case {
    let chunk = g.range(1, 40);
    let paths = g.range(1, chunk * 30);
    let chunks = paths.div_ceil(chunk);
    let ring = Ring { paths, chunk, ring: g.range(1, chunks.min(MAX_RING)) };
    let oldest = g.range(0, chunks - 1);
    let first = oldest * chunk;
    let started =
        if g.chance(30) { ring.fill_limit(oldest) } else { g.range(first, ring.fill_limit(oldest)) };
    let started_before = g.range(first.min(started), started);
    let mut counts = vec![0u32; ring.ring as usize];
    for c in oldest..chunks.min(oldest + ring.ring) {
        let begun = started.min(ring.end(c)).saturating_sub(c * chunk);
        let done = if g.chance(50) { begun } else { g.range(0, begun) };
        counts[(c % ring.ring) as usize] = done;
    }
    let finished = first + counts.iter().sum::<u32>();
    let threshold = g
        .chance(80)
        .then(|| [0.05, 0.1, 0.25, 0.5, 1.0, g.range(1, 1000) as f64 / 1000.0][g.range(0, 5) as usize]);
    Case {
        ring,
        pool: chunk,
        oldest,
        started_before,
        counters: ChunkCounters { started, finished, ring: counts },
        threshold,
    }
}

#[test]
fn the_gpu_decides_as_the_host_rule() {
    let Some(ctx) = common::gpu() else { return };
    let mut g = Rng(0x9e37_79b9_7f4a_7c15);
    let cases: Vec<Case> = (0..4096).map(|_| random_case(&mut g)).collect();
    let mut words = vec![0u32; cases.len() * CASE_WORDS];
    for (i, c) in cases.iter().enumerate() {
        let w = &mut words[i * CASE_WORDS..(i + 1) * CASE_WORDS];
        // The host hands the GPU floor(threshold × pool): Rust compares with the product itself.
        let max_live = c.threshold.map_or(0, |t| (t * c.pool as f64).floor() as u32);
        w[..9].copy_from_slice(&[
            c.ring.paths,
            c.ring.chunk,
            c.ring.ring,
            c.oldest,
            c.counters.started,
            c.started_before,
            c.counters.finished,
            max_live,
            c.threshold.is_some() as u32,
        ]);
        w[9..9 + c.counters.ring.len()].copy_from_slice(&c.counters.ring);
    }
    let input = storage_init(ctx, "cases", &words, wgpu::BufferUsages::empty()).unwrap();
    let out_bytes = cases.len() as u64 * 16;
    let out = storage_zeroed(ctx, "decided", out_bytes, wgpu::BufferUsages::COPY_SRC).unwrap();
    let layout = ctx.bind_group_layout("schedule probe", &[storage_entry(0, true), storage_entry(1, false)]);
    let group = ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: None,
        layout: &layout,
        entries: &[
            wgpu::BindGroupEntry { binding: 0, resource: input.as_entire_binding() },
            wgpu::BindGroupEntry { binding: 1, resource: out.as_entire_binding() },
        ],
    });
    let module = ctx.shader("schedule_probe", shaders::SCHEDULE_PROBE, Default::default()).unwrap();
    let probe = ctx.compute_pipeline("schedule_probe", &module, &[&layout], &[]).unwrap();
    let mut enc = ctx.device.create_command_encoder(&Default::default());
    {
        let mut pass = enc.begin_compute_pass(&Default::default());
        pass.set_pipeline(&probe);
        pass.set_bind_group(0, &group, &[]);
        pass.dispatch_workgroups((cases.len() as u32).div_ceil(64), 1, 1);
    }
    ctx.queue.submit([enc.finish()]);
    let got: Vec<u32> = read_back(ctx, &out, out_bytes).unwrap();
    let (mut tails, mut flushes, mut adds, mut done) = (0, 0, 0, 0);
    for (i, c) in cases.iter().enumerate() {
        let want = Decision::after(&c.ring, &c.counters, c.oldest, c.started_before, c.pool, c.threshold);
        let d = &got[4 * i..4 * i + 4];
        let gpu = Decision {
            refill: d[0] != 0,
            complete: d[1],
            tail_bound: (d[2] != 0).then_some(d[2]),
            added: d[3],
        };
        assert_eq!(
            gpu, want,
            "case {i}: {:?} oldest {} started before {} counters {:?} {:?} threshold {:?}",
            c.ring, c.oldest, c.started_before, c.counters.started, c.counters.ring, c.threshold
        );
        tails += want.tail_bound.is_some_and(|b| b == c.ring.chunks()) as u32;
        flushes += want.tail_bound.is_some_and(|b| b < c.ring.chunks()) as u32;
        adds += (want.added > c.oldest) as u32;
        done += (want.added == c.ring.chunks()) as u32;
    }
    // The cases reach every branch of the rule, often.
    eprintln!("{tails} final tails, {flushes} flushes, {adds} with chunks added, {done} done");
    for (what, n) in [("final tails", tails), ("flushes", flushes), ("additions", adds), ("ends", done)] {
        assert!(n >= 20, "only {n} {what} among the cases");
    }
}
