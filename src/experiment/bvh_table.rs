//! The report page's BVH section (issue 59): per run, the layout traversed, its nodes, memory,
//! depth and build time, and with `instrument` the traversal counts per ray on the CPU twin's
//! paths (closest-hit and shadow rays together), the figures that predict a traversal's cost
//! on any device.

use super::report::RunRecord;
use std::fmt::Write as _;

/// The section, or nothing when no run recorded its BVH (reports from before).
pub fn table(runs: &[RunRecord]) -> String {
    let with: Vec<&RunRecord> = runs.iter().filter(|r| r.bvh.is_some()).collect();
    if with.is_empty() {
        return String::new();
    }
    let mut md = String::from(
        "## BVH\n\nThe layout each run traversed, its nodes, their bytes, its depth and its build \
         (binary SAH, then the layout's conversion; median host seconds over the timed \
         repetitions). With `instrument`, per ray (closest-hit and shadow rays together, on the \
         CPU reference's paths, whose traversal loops are the GPU's twins step for step): BVH \
         bytes fetched, node fetches, primitive tests, loop iterations and the deepest stack.\n\n\
         | # | scene | variant | layout | nodes | bytes | depth | build | bytes per ray | node fetches per ray | primitive tests per ray | iterations per ray | deepest stack |\n\
         | ---: | --- | --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n",
    );
    for r in with {
        let b = r.bvh.as_ref().expect("filtered");
        let t = r.traversal.map(|t| t.all);
        let per_ray = |f: fn(&crate::cpu::traversal_counts::RayCounts) -> f64| {
            t.as_ref().map_or("–".into(), |t| format!("{:.2}", f(t)))
        };
        let _ = writeln!(
            md,
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |",
            r.index,
            r.scene,
            r.label,
            b.layout.name(),
            b.nodes,
            b.bytes,
            b.depth,
            r.bvh_build_seconds.map_or("–".into(), |s| format!("{s:.3} s")),
            per_ray(|t| t.bvh_bytes),
            per_ray(|t| t.node_fetches),
            per_ray(|t| t.primitive_tests),
            per_ray(|t| t.iterations),
            t.map_or("–".into(), |t| t.deepest_stack.to_string()),
        );
    }
    md.push('\n');
    md
}
