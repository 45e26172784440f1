//! The recorded paths of one dispatch (or wavefront share): every sample's events, recorded in
//! parallel on the CPU reference, indexed by the sample's index in the dispatch as the GPU
//! kernels index it (pixel `pixel_offset + i % pixel_count`, sample `sample_start + i /
//! pixel_count`).

use super::lockstep::Lane;
use super::recorder::Recorder;
use crate::cpu::{camera::Camera, integrator::trace_path};
use crate::layout::DispatchParams;
use crate::packed_scene::PackedScene;
use crate::settings::RenderSettings;
use rayon::prelude::*;
use std::ops::Range;

/// Samples recorded per parallel task.
const CHUNK: usize = 1024;

pub struct Paths {
    events: Vec<u32>,
    spans: Vec<Range<usize>>,
}

impl Paths {
    /// Records samples `range` of dispatch `d` (all of them: `0..pixel_count × sample_count`).
    pub fn record(
        scene: &PackedScene,
        camera: &Camera<f32>,
        settings: &RenderSettings,
        d: &DispatchParams,
        range: Range<u64>,
    ) -> Self {
        let starts: Vec<u64> = range.clone().step_by(CHUNK).collect();
        let parts: Vec<(Vec<u32>, Vec<Range<usize>>)> = starts
            .par_iter()
            .map(|&first| {
                let mut rec = Recorder::default();
                let mut spans = Vec::with_capacity(CHUNK);
                for i in first..(first + CHUNK as u64).min(range.end) {
                    let pixel = d.pixel_offset + (i % d.pixel_count as u64) as u32;
                    let sample = d.sample_start + (i / d.pixel_count as u64) as u32;
                    let start = rec.events.len();
                    let (x, y) = (pixel % settings.width, pixel / settings.width);
                    trace_path(scene, camera, settings, x, y, sample, &mut rec);
                    spans.push(start..rec.events.len());
                }
                (rec.events, spans)
            })
            .collect();
        let mut out = Paths { events: Vec::new(), spans: Vec::new() };
        for (events, spans) in parts {
            let base = out.events.len();
            out.spans.extend(spans.into_iter().map(|s| s.start + base..s.end + base));
            out.events.extend(events);
        }
        out
    }

    pub fn len(&self) -> usize {
        self.spans.len()
    }

    pub fn is_empty(&self) -> bool {
        self.spans.is_empty()
    }

    /// Path `i` (from the recorded range's start) as a lane at its first event.
    pub fn lane(&self, i: usize) -> Lane<'_> {
        Lane { events: &self.events[self.spans[i].clone()], at: 0 }
    }

    /// Every recorded path as a lane, in index order.
    pub fn lanes(&self) -> Vec<Lane<'_>> {
        (0..self.len()).map(|i| self.lane(i)).collect()
    }
}
