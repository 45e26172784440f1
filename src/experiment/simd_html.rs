//! report.html's SIMD-efficiency table: per instrumented run, the frame's work-weighted figure
//! (the counterpart of nvprof's warp execution efficiency) and, per pass, the work-weighted
//! figure beside the entry-point one (`src/gpu/instrument.rs` says which is which).

use std::fmt::Write;

use super::escape::esc;
use super::report::ExperimentReport;
use crate::gpu::instrument::{FRAME_KEY, WORK_PREFIX};

/// The entry-point slot shown beside a pass's work-weighted figure.
fn entry_slot(pass: &str) -> &str {
    match pass {
        "megakernel" => "megakernel_bounce",
        p => p,
    }
}

pub fn simd_table(h: &mut String, report: &ExperimentReport) {
    let runs: Vec<_> =
        report.runs.iter().filter_map(|r| Some((r, r.simd.as_ref().filter(|s| !s.is_empty())?))).collect();
    if runs.is_empty() {
        return;
    }
    h.push_str(
        "<h2>SIMD efficiency</h2><p>From a separate instrumented render. <b>Work-weighted</b>: active \
         lanes ÷ (subgroup width × subgroup-iterations issued) over every instrumented block, the BVH \
         traversal loop's steps included, so lanes whose rays finished early count idle while their \
         neighbours traverse; the frame figure is the counterpart of nvprof's warp execution \
         efficiency (which weights by instructions, this by executed blocks). <b>Entry</b>: lanes \
         active when a subgroup reaches the pass's body (the top of a bounce in a megakernel), \
         the narrower figure earlier reports gave. In the wavefront, <code>megakernel</code> is its \
         tail. Subgroup width: the device's.</p>\
         <div class=\"scroll\"><table><tr><th>#</th><th class=\"l\">scene</th><th class=\"l\">method</th>\
         <th>warp execution efficiency</th><th class=\"l\">per pass: work-weighted (entry)</th></tr>\n",
    );
    for (r, simd) in runs {
        let pct = |k: &str| simd.get(k).map_or("–".into(), |e| format!("{:.1}%", e.efficiency * 100.0));
        let passes: Vec<String> = simd
            .keys()
            .filter_map(|k| k.strip_prefix(WORK_PREFIX))
            .map(|p| format!("{}: {} ({})", esc(p), pct(&format!("{WORK_PREFIX}{p}")), pct(entry_slot(p))))
            .collect();
        let _ = writeln!(
            h,
            "<tr><td>{}</td><td class=\"l\">{}</td><td class=\"l\">{}</td><td>{}</td><td class=\"l\">{}</td></tr>",
            r.index,
            esc(&r.scene),
            esc(&r.label),
            pct(FRAME_KEY),
            passes.join("; ")
        );
    }
    h.push_str("</table></div>\n");
}
