//! `report.html`: the report's tables, charts, and each run's image beside its reference and a
//! false-colour error map. Self-contained (charts inline as SVG, images as `data:` URIs of small
//! previews), so it opens from disk in a browser with no server and survives being mailed.

use crate::gpu::buffers::human_bytes;
use crate::gpu::memory::MemoryCategory;
use std::fmt::Write as _;
use std::path::Path;

use super::charts::Chart;
use super::error_map::{self, MAP_DECADES};
use super::escape::esc;
use super::method_colours::MethodColours;
use super::report::{ExperimentReport, ReportStatus, RunRecord, RunStatus};
use super::stability::FLAG;
use super::verdict::Verdict;
use crate::chart::viridis;

/// Width of the image previews embedded in the page.
const PREVIEW_WIDTH: u32 = 320;

const STYLE: &str = "body{font-family:sans-serif;margin:2em;max-width:1500px;color:#222}\
table{border-collapse:collapse;font-size:13px;margin:1em 0}\
th,td{border:1px solid #ccc;padding:3px 6px;text-align:right}th{background:#f3f3f3}\
td.l,th.l{text-align:left}tr.failed td{background:#fde8e8}tr.flagged td{background:#fff6d6}\
.scroll{overflow-x:auto;max-width:100%}.scroll table{margin:.5em 0}\
.charts{display:flex;flex-wrap:wrap;gap:1em}.charts svg{max-width:100%;height:auto}\
figure{display:inline-block;margin:0 1em 1em 0;vertical-align:top}figcaption{font-size:12px;max-width:320px}\
.run{border-top:1px solid #ddd;padding-top:.5em}.q{font-style:italic;color:#444}\
#verdict{background:#f4f8fb;border:1px solid #c9dbe8;padding:.2em 1em;margin:1em 0}\
#verdict li{margin:.3em 0}.caveat{font-weight:bold;color:#8a4b00}\
.legend span{display:inline-block;margin-right:1.2em;font-size:14px}\
.legend i{display:inline-block;width:14px;height:14px;margin-right:.4em;vertical-align:middle}\
.scale{display:inline-block;width:200px;height:12px;vertical-align:middle}code,pre{font-size:12px}";

/// The whole page: the verdict first, then the charts, then the tables in boxes of their own
/// that scroll sideways rather than overflow the page. `dir` holds the report's images
/// (missing ones are said to be missing).
pub fn page(report: &ExperimentReport, charts: &[Chart], dir: &Path) -> String {
    let mut h = String::new();
    let name = esc(&report.name);
    let _ = write!(
        h,
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>wavetrace: {name}</title>\
         <style>{STYLE}</style></head><body>\n<h1>wavetrace experiment: {name}</h1>\n<p class=\"q\">{}</p>\n",
        esc(&report.question)
    );
    status(&mut h, report);
    verdict(&mut h, report);
    charts_section(&mut h, report, charts);
    runs_table(&mut h, report);
    super::simd_html::simd_table(&mut h, report);
    memory_table(&mut h, report);
    environments(&mut h, report);
    images(&mut h, report, dir);
    let _ = writeln!(
        h,
        "<h2>Config</h2><details><summary>as run</summary><pre>{}</pre></details>",
        esc(&serde_json::to_string_pretty(&report.config).unwrap_or_default())
    );
    h.push_str("<p>Written by <code>wavetrace experiment</code>; the numbers are in report.json beside this file.</p>\n</body></html>\n");
    h
}

fn status(h: &mut String, report: &ExperimentReport) {
    let ok = report.runs.iter().filter(|r| r.status == RunStatus::Ok).count();
    let status = match report.status {
        ReportStatus::Running => "running or interrupted: the runs below are those that finished",
        ReportStatus::Complete => "complete",
        ReportStatus::Incomplete => "incomplete: some planned runs are missing",
    };
    let _ = writeln!(
        h,
        "<p>Status: <b>{status}</b>. {ok} runs succeeded, {} failed, of {} selected ({} in the config). \
         Config: <code>{}</code>.</p>",
        report.runs.len() - ok,
        report.runs_selected,
        report.runs_planned,
        esc(&report.config_file)
    );
    if !report.missing_runs.is_empty() {
        let _ = writeln!(h, "<p>Missing runs (by index): {:?}</p>", report.missing_runs);
    }
}

/// The verdict ([`Verdict`]): the software-driver caveat, then one item per job.
fn verdict(h: &mut String, report: &ExperimentReport) {
    let v = Verdict::of(report);
    h.push_str("<section id=\"verdict\"><h2>Verdict</h2>\n");
    if let Some(c) = &v.caveat {
        let _ = writeln!(h, "<p class=\"caveat\">{}</p>", esc(c));
    }
    if v.jobs.is_empty() {
        h.push_str("<p>No run finished with a time.</p>\n");
    } else {
        let _ = writeln!(
            h,
            "<p>Per job: the fastest method, and each other's speed as a multiple of its speed (below 1: \
             slower); relMSE against the reference. {FLAG}: not a steady figure (see the runs table).</p><ul>"
        );
        for j in &v.jobs {
            let _ = writeln!(h, "<li><b>{}</b>: {}</li>", esc(&j.job), esc(&j.sentences.join(" ")));
        }
        h.push_str("</ul>\n");
        if let Some(more) = v.omitted_line() {
            let _ = writeln!(h, "<p>{}</p>", esc(&more));
        }
    }
    h.push_str("</section>\n");
}

/// The charts, grouped by scene and size, under one legend: each method variant has one colour
/// in every chart ([`MethodColours`]).
fn charts_section(h: &mut String, report: &ExperimentReport, charts: &[Chart]) {
    h.push_str("<h2>Charts</h2>\n");
    if charts.is_empty() {
        h.push_str("<p>No chart: no run succeeded with data to chart.</p>\n");
        return;
    }
    h.push_str("<p class=\"legend\">One colour per method variant in every chart: ");
    for (label, colour) in MethodColours::of(report).legend() {
        let _ = write!(h, "<span><i style=\"background:{colour}\"></i>{}</span>", esc(&label));
    }
    h.push_str("</p>\n");
    let mut last_group = None;
    for c in charts {
        let group = (c.scene.as_str(), c.width, c.height);
        if last_group != Some(group) {
            if last_group.is_some() {
                h.push_str("</div>\n");
            }
            let heading = if c.scene.is_empty() {
                "Across scenes".to_string()
            } else if c.width == 0 {
                format!("{}, across job sizes", esc(&c.scene))
            } else {
                format!("{} {}x{}", esc(&c.scene), c.width, c.height)
            };
            let _ = writeln!(h, "<h3>{heading}</h3><div class=\"charts\">");
            last_group = Some(group);
        }
        h.push_str(strip_prolog(&c.svg));
        h.push('\n');
    }
    h.push_str("</div>\n");
}

fn environments(h: &mut String, report: &ExperimentReport) {
    h.push_str(
        "<h2>Where it ran</h2><div class=\"scroll\"><table><tr><th>#</th><th class=\"l\">shard</th><th class=\"l\">host</th>\
         <th class=\"l\">CPU</th><th>cores</th><th class=\"l\">adapter</th><th class=\"l\">backend</th>\
         <th class=\"l\">driver</th><th class=\"l\">commit</th><th class=\"l\">started</th><th class=\"l\">finished</th></tr>\n",
    );
    for (i, e) in report.environments.iter().enumerate() {
        let s = |v: &serde_json::Value, k: &str| esc(v.get(k).and_then(|x| x.as_str()).unwrap_or(""));
        let a = e.adapter.clone().unwrap_or_default();
        let _ = writeln!(
            h,
            "<tr><td>{i}</td><td class=\"l\">{}</td><td class=\"l\">{}</td><td class=\"l\">{}</td><td>{}</td>\
             <td class=\"l\">{}</td><td class=\"l\">{}</td><td class=\"l\">{} {}</td><td class=\"l\">{}</td>\
             <td class=\"l\">{}</td><td class=\"l\">{}</td></tr>",
            e.shard.map_or("-".into(), |s| s.to_string()),
            s(&e.machine, "hostname"),
            s(&e.machine, "cpu"),
            e.machine.get("logical_cores").and_then(|x| x.as_u64()).unwrap_or(0),
            if e.adapter.is_some() { s(&a, "name") } else { "(no GPU run)".into() },
            s(&a, "backend"),
            s(&a, "driver"),
            s(&a, "driver_info"),
            s(&e.build, "git_commit"),
            esc(&e.started),
            esc(e.finished.as_deref().unwrap_or("-")),
        );
    }
    h.push_str("</table></div>\n");
}

fn runs_table(h: &mut String, report: &ExperimentReport) {
    h.push_str(
        "<h2>Runs</h2><p>Time: median over repetitions [min–max]: frame time for GPU methods (first \
         submission to last completion, host round trips included), wall time for CPU methods. \
         Spread: (max − min) ÷ median of the repetitions; warm-up: the untimed renders before them. \
         × fastest megakernel: the fastest megakernel variant's time for the same job over this run's (above 1 \
         is faster), with the interval its medians' intervals allow. ⚠: not a steady figure — \
         repetitions spread beyond the config's threshold (unstable) or a GPU run without warm-up \
         (cold); its row is shaded. relMSE uses ε = 0.01 (pbrt-v4); efficiency = 1/(relMSE·time). \
         Dispatches: compute passes per render (empty: indirect ones sized to zero workgroups); \
         occupancy: the wavefront's mean paths per intersect pass ÷ pool. Where the numerics failed, \
         per render: NaN/Inf samples dropped; self-hits, secondary rays whose closest hit was the \
         primitive they left; shadow self-hits, shadow rays likewise; depth-cut, paths still going \
         at the max depth (cut, their light lost).</p>\
         <div class=\"scroll\"><table><tr><th>#</th><th class=\"l\">scene</th><th>size</th><th>spp</th><th>depth</th><th class=\"l\">method</th>\
         <th>time s</th><th>[min–max]</th><th>spread</th><th class=\"l\">warm-up</th><th>× fastest megakernel</th><th>Msamples/s</th><th>Mrays/s</th><th>NaN/Inf</th><th>self-hits</th><th>shadow self-hits</th>\
         <th>depth-cut</th><th>MSE</th>\
         <th>relMSE</th><th>SMAPE</th><th>FLIP</th><th>efficiency</th><th>dispatches (empty)</th>\
         <th>occupancy</th><th class=\"l\">note</th></tr>\n",
    );
    let threshold = super::stability::threshold_of(&report.config);
    let fastest = super::baseline::fastest_megakernel(report);
    for r in &report.runs {
        let st = super::stability::of_run(r, threshold);
        let flagged = r.status == RunStatus::Ok && st.flagged();
        let versus = super::baseline::versus_megakernel(r, &fastest, threshold).map_or("–".into(), |v| {
            format!(
                "{:.2}×{} [{:.2}–{:.2}]",
                v.ratio,
                super::stability::flag(v.flagged),
                v.interval.0,
                v.interval.1
            )
        });
        let spread = st.spread.map_or("–".into(), |x| {
            format!(
                "{:.1}%{}",
                100.0 * x,
                if st.unstable { format!(" {FLAG} unstable") } else { String::new() }
            )
        });
        let warmup = warmup_cell(r, st.cold);
        let g = |x: Option<f64>, scale: f64, prec: usize| {
            x.map_or("–".into(), |v| format!("{:.*}", prec, v * scale))
        };
        let e = |x: Option<f64>| x.map_or("–".into(), |v| format!("{v:.3e}"));
        let count = |x: Option<u64>| x.map_or("–".into(), |n| n.to_string());
        let stat = r.timed_stat();
        let m = r.error_metrics.as_ref();
        let note = match (&r.status, r.repeatable) {
            (RunStatus::Failed, _) => format!("FAILED: {}", esc(r.error.as_deref().unwrap_or(""))),
            (_, Some(false)) => "repetitions differ".into(),
            _ => String::new(),
        };
        let _ = writeln!(
            h,
            "<tr{}><td>{}</td><td class=\"l\">{}</td><td>{}x{}</td><td>{}</td><td>{}</td><td class=\"l\">{}</td>\
             <td>{}</td><td>{}</td><td>{spread}</td><td class=\"l\">{}</td><td>{versus}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td>\
             <td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td class=\"l\">{note}</td></tr>",
            match (r.status, flagged) {
                (RunStatus::Failed, _) => " class=\"failed\"",
                (_, true) => " class=\"flagged\"",
                _ => "",
            },
            r.index,
            esc(&r.scene),
            r.width,
            r.height,
            r.spp,
            r.max_depth,
            esc(&r.label),
            g(r.seconds, 1.0, 4) + super::stability::flag(flagged),
            stat.map_or("–".into(), |s| format!("{:.4}–{:.4}", s.min, s.max)),
            esc(&warmup),
            g(r.samples_per_second, 1e-6, 3),
            g(r.rays_per_second, 1e-6, 3),
            count(r.invalid_samples),
            count(r.self_hits),
            count(r.shadow_self_hits),
            count(r.depth_cut),
            e(m.map(|m| m.mse)),
            e(m.map(|m| m.relmse)),
            g(m.map(|m| m.smape), 1.0, 4),
            g(m.and_then(|m| m.flip), 1.0, 4),
            e(r.efficiency),
            match (r.dispatches.filter(|&d| d > 0), r.empty_dispatches) {
                (Some(d), Some(empty)) => format!("{d} ({empty})"),
                (Some(d), None) => d.to_string(),
                _ => "–".into(),
            },
            r.intersect_occupancy.map_or("–".into(), |o| format!("{:.1}%", o * 100.0)),
        );
    }
    h.push_str("</table></div>\n");
}

/// How a run warmed up, flagged where a GPU run was not warmed (cold).
fn warmup_cell(r: &RunRecord, cold: bool) -> String {
    let warmup = match &r.warmup_log {
        Some(w) => format!(
            "{} ({} frames, {:.3} s{})",
            w.policy,
            w.frames,
            w.seconds,
            if w.settled { "" } else { ", unsettled" }
        ),
        None if r.warmup == 1 => "1 frame".to_string(),
        None => format!("{} frames", r.warmup),
    };
    warmup + &if cold { format!(" {FLAG} cold") } else { String::new() }
}

/// GPU memory per GPU run, by category: what each method pays in memory for its speed.
fn memory_table(h: &mut String, report: &ExperimentReport) {
    let runs: Vec<_> = report.runs.iter().filter_map(|r| Some((r, r.memory.as_ref()?))).collect();
    if runs.is_empty() {
        return;
    }
    let used: Vec<MemoryCategory> = MemoryCategory::ALL
        .into_iter()
        .filter(|c| runs.iter().any(|(_, m)| m.by_category.contains_key(c.key())))
        .collect();
    h.push_str(
        "<h2>GPU memory</h2><p>Bytes each GPU run asked wgpu for, by category (the driver may reserve \
         more); peak: everything held at once, the film's read-back copy included. Per path: the \
         method's per-path buffers over the paths in flight.</p><div class=\"scroll\"><table><tr><th>#</th>\
         <th class=\"l\">scene</th><th>size</th><th>spp</th><th class=\"l\">method</th>",
    );
    for c in &used {
        let _ = write!(h, "<th>{}</th>", c.key().replace('_', " "));
    }
    h.push_str("<th>total</th><th>peak</th><th>per path</th></tr>\n");
    for (r, m) in runs {
        let _ = write!(
            h,
            "<tr><td>{}</td><td class=\"l\">{}</td><td>{}x{}</td><td>{}</td><td class=\"l\">{}</td>",
            r.index,
            esc(&r.scene),
            r.width,
            r.height,
            r.spp,
            esc(&r.label)
        );
        for c in &used {
            let cell = m.by_category.get(c.key()).map_or("–".into(), |&b| human_bytes(b));
            let _ = write!(h, "<td>{cell}</td>");
        }
        let per_path = r.bytes_per_path.map_or("–".into(), |b| format!("{b} B"));
        let _ = writeln!(
            h,
            "<td>{}</td><td>{}</td><td>{per_path}</td></tr>",
            human_bytes(m.total),
            human_bytes(m.peak)
        );
    }
    h.push_str("</table></div>\n");
}

fn images(h: &mut String, report: &ExperimentReport, dir: &Path) {
    let scale: Vec<String> =
        (0..=10).map(|i| crate::chart::hex(viridis(i as f32 / 10.0))).map(|c| c.to_string()).collect();
    let _ = writeln!(
        h,
        "<h2>Images</h2><p>Each run beside its reference and its error map: per-pixel relative squared error \
         (v−r)²/(r+0.01)², averaged over channels, on a log scale from 10<sup>{}</sup> \
         <span class=\"scale\" style=\"background:linear-gradient(to right,{})\"></span> 10<sup>{}</sup> \
         (magenta: NaN/Inf). Previews are sRGB, clamped to [0, 1]; full-size files are under images/.</p>",
        MAP_DECADES.0,
        scale.join(","),
        MAP_DECADES.1
    );
    for r in report.runs.iter().filter(|r| r.status == RunStatus::Ok) {
        let _ = writeln!(h, "<div class=\"run\"><h3>{}</h3>", esc(&r.id));
        let Some(images) = &r.images else { continue };
        figure(h, dir, &images.png, &format!("{}: {} spp, {}", esc(&r.label), r.spp, caption_time(r)));
        let reference = r.reference.as_ref().and_then(|k| report.references.iter().find(|x| &x.key == k));
        if let Some(reference) = reference {
            let how = match (&reference.method, reference.spp) {
                (Some(m), Some(spp)) if reference.spp_match => {
                    format!("{} at {spp} spp, the run's seed", esc(m))
                }
                (Some(m), Some(spp)) => format!("{} at {spp} spp", esc(m)),
                _ => esc(&reference.exr),
            };
            figure(h, dir, reference.png.as_deref().unwrap_or(""), &format!("reference: {how}"));
        }
        if let (Some(map), Some(m)) = (&images.error_map, &r.error_metrics) {
            figure(h, dir, map, &format!("error: relMSE {:.3e}, MSE {:.3e}", m.relmse, m.mse));
        }
        h.push_str("</div>\n");
    }
}

fn caption_time(r: &RunRecord) -> String {
    r.seconds.map_or(String::new(), |s| format!("{s:.4} s"))
}

/// An `<img>` of a preview of the PNG at `dir/file`, or a note that it is missing.
fn figure(h: &mut String, dir: &Path, file: &str, caption: &str) {
    let img = match thumbnail_data_uri(&dir.join(file)) {
        Some(uri) => format!("<a href=\"{}\"><img src=\"{uri}\" alt=\"{}\"></a>", esc(file), esc(file)),
        None => format!("<p>({} not available)</p>", esc(file)),
    };
    let _ = writeln!(h, "<figure>{img}<figcaption>{caption}</figcaption></figure>");
}

fn thumbnail_data_uri(path: &Path) -> Option<String> {
    let (width, height, pixels) = crate::image_io::read_png_rgb8(path).ok()?;
    let (w, h, rgb) = error_map::downscale(width, height, &pixels, PREVIEW_WIDTH);
    let png = crate::image_io::encode_png_rgb8(w, h, &rgb).ok()?;
    Some(format!("data:image/png;base64,{}", base64(&png)))
}

/// Chart SVGs are standalone documents; inline in HTML they must not carry an XML prolog.
fn strip_prolog(svg: &str) -> &str {
    match svg.find("<svg") {
        Some(i) => &svg[i..],
        None => svg,
    }
}

/// Standard base64 (RFC 4648, with padding).
pub fn base64(bytes: &[u8]) -> String {
    const ALPHABET: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::with_capacity(bytes.len().div_ceil(3) * 4);
    for chunk in bytes.chunks(3) {
        let b = [chunk[0], chunk.get(1).copied().unwrap_or(0), chunk.get(2).copied().unwrap_or(0)];
        let n = (u32::from(b[0]) << 16) | (u32::from(b[1]) << 8) | u32::from(b[2]);
        for i in 0..4 {
            if i <= chunk.len() {
                out.push(ALPHABET[(n >> (18 - 6 * i) & 63) as usize] as char);
            } else {
                out.push('=');
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn base64_matches_rfc4648_vectors() {
        for (input, expected) in [
            ("", ""),
            ("f", "Zg=="),
            ("fo", "Zm8="),
            ("foo", "Zm9v"),
            ("foob", "Zm9vYg=="),
            ("fooba", "Zm9vYmE="),
            ("foobar", "Zm9vYmFy"),
        ] {
            assert_eq!(base64(input.as_bytes()), expected);
        }
    }
}
