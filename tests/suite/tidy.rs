//! `runs.csv` and `passes.csv` read back with an RFC 4180 reader of their own (not the writer's
//! code) say what report.json says: one row per run (per run × pass), every value, commas and
//! quotes in strings intact; `experiment report` and `merge` rewrite them.

use std::path::Path;

use serde_json::Value;

use crate::experiment::{assert_valid, scratch, wavetrace, write_config};

/// RFC 4180 records: fields split on commas outside quotes, `""` inside quotes is `"`, records
/// end with CRLF (a bare LF inside quotes is data).
pub fn parse_csv(text: &str) -> Vec<Vec<String>> {
    let mut records = Vec::new();
    let mut record = Vec::new();
    let mut field = String::new();
    let mut chars = text.chars().peekable();
    let mut quoted = false;
    while let Some(c) = chars.next() {
        match (quoted, c) {
            (true, '"') if chars.peek() == Some(&'"') => {
                chars.next();
                field.push('"');
            }
            (true, '"') => quoted = false,
            (true, c) => field.push(c),
            (false, '"') => {
                assert!(field.is_empty(), "a quote inside an unquoted field: {field:?}");
                quoted = true;
            }
            (false, ',') => record.push(std::mem::take(&mut field)),
            (false, '\r') => {
                assert_eq!(chars.next(), Some('\n'), "CR without LF");
                record.push(std::mem::take(&mut field));
                records.push(std::mem::take(&mut record));
            }
            (false, c) => {
                assert!(c != '\n', "a bare LF ends a record: RFC 4180 wants CRLF");
                field.push(c);
            }
        }
    }
    assert!(!quoted && field.is_empty() && record.is_empty(), "the last record lacks its CRLF");
    records
}

/// Whether a cell says what the JSON value says: empty for null, numbers to within float
/// parsing's last bit (serde_json's default float reader may be one ulp off).
fn same(cell: &str, v: &Value) -> bool {
    match v {
        Value::Null => cell.is_empty(),
        Value::String(s) => cell == s,
        Value::Bool(b) => cell == b.to_string(),
        Value::Number(n) => {
            let (a, b) = (cell.parse::<f64>().unwrap_or(f64::NAN), n.as_f64().unwrap());
            a == b || (a - b).abs() <= 4.0 * f64::EPSILON * b.abs()
        }
        other => serde_json::from_str::<Value>(cell).is_ok_and(|v| &v == other),
    }
}

/// A CSV file as (header, rows), every row as long as the header, column names unique.
fn read(dir: &Path, file: &str) -> (Vec<String>, Vec<Vec<String>>) {
    let text = std::fs::read_to_string(dir.join(file)).unwrap_or_else(|e| panic!("{file}: {e}"));
    let mut records = parse_csv(&text);
    assert!(!records.is_empty(), "{file} has no header");
    let header = records.remove(0);
    let mut names = header.clone();
    names.sort();
    names.dedup();
    assert_eq!(names.len(), header.len(), "{file}: column names repeat: {header:?}");
    for r in &records {
        assert_eq!(
            r.len(),
            header.len(),
            "{file}: a row of {} cells under {} columns",
            r.len(),
            header.len()
        );
    }
    (header, records)
}

/// Checks `runs.csv` and `passes.csv` in `dir` against its report.json; returns runs.csv's
/// header and rows.
pub fn assert_tidy(dir: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    let report: Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("report.json")).unwrap()).unwrap();
    let runs = report["runs"].as_array().unwrap();

    let (header, rows) = read(dir, "runs.csv");
    let at = |name: &str| header.iter().position(|h| h == name).unwrap_or_else(|| panic!("no column {name}"));
    assert_eq!(rows.len(), runs.len(), "one row per run");
    for (row, r) in rows.iter().zip(runs) {
        let mut expected: Vec<(String, &Value)> = [
            "index",
            "id",
            "scene",
            "width",
            "height",
            "spp",
            "max_depth",
            "nee",
            "roulette",
            "seed",
            "accel",
            "method",
            "label",
            "status",
            "error",
            "resumed",
            "environment",
            "warmup",
            "repetitions",
            "time_source",
            "seconds",
            "samples",
            "samples_per_second",
            "rays",
            "rays_per_second",
            "dispatches",
            "invalid_samples",
            "self_hits",
            "shadow_self_hits",
            "depth_cut",
            "image_mean",
            "repeatable",
            "bytes_per_path",
            "indirect_validation",
            "reference",
            "efficiency",
            "empty_dispatches",
            "iterations",
            "idle_iterations",
            "intersect_occupancy",
        ]
        .iter()
        .map(|k| (k.to_string(), &r[*k]))
        .collect();
        for (stat, col) in [("wall_seconds", "wall_seconds"), ("gpu_seconds", "gpu_seconds")] {
            for part in ["median", "min", "max"] {
                expected.push((format!("{col}_{part}"), &r[stat][part]));
            }
        }
        expected.push(("pool_size_used".into(), &r["pool_size"]));
        // GPU memory: one column per category (empty where the run has none), total and peak.
        for category in wavetrace::gpu::memory::MemoryCategory::ALL {
            let key = category.key();
            expected.push((format!("memory_{key}"), &r["memory"]["by_category"][key]));
        }
        expected.push(("memory_total".into(), &r["memory"]["total"]));
        expected.push(("memory_peak".into(), &r["memory"]["peak"]));
        for k in ["exr", "png", "error_map"] {
            expected.push((k.into(), &r["images"][k]));
        }
        for k in ["mse", "rmse", "relmse", "smape", "mape", "flip"] {
            expected.push((k.into(), &r["error_metrics"][k]));
        }
        if let Some(m) = r["error_metrics"].as_object() {
            expected.extend(m.iter().map(|(k, v)| (k.clone(), v)));
        }
        for (k, v) in r["options"].as_object().unwrap() {
            expected.push((k.clone(), v));
        }
        for (name, v) in expected {
            let cell = &row[at(&name)];
            assert!(same(cell, v), "{} {}: runs.csv says {cell:?}, report.json {v}", r["id"], name);
        }
        // The time `seconds` is the median of, with its spread.
        if let Ok(t) = row[at("seconds")].parse::<f64>() {
            let lo: f64 = row[at("seconds_min")].parse().unwrap();
            let hi: f64 = row[at("seconds_max")].parse().unwrap();
            assert!(lo <= t && t <= hi, "{}: {lo} <= {t} <= {hi}", r["id"]);
        }
    }

    let (pheader, prows) = read(dir, "passes.csv");
    let pat =
        |name: &str| pheader.iter().position(|h| h == name).unwrap_or_else(|| panic!("no column {name}"));
    let mut expected_rows = 0;
    for r in runs {
        let mut labels: Vec<&String> = r["passes"].as_object().unwrap().keys().collect();
        if let Some(s) = r["simd"].as_object() {
            labels.extend(s.keys());
        }
        labels.sort();
        labels.dedup();
        let mine: Vec<&Vec<String>> = prows.iter().filter(|p| p[pat("run_id")] == r["id"]).collect();
        assert_eq!(mine.len(), labels.len(), "{}: one passes.csv row per pass label", r["id"]);
        expected_rows += labels.len();
        let mut share = 0.0;
        for p in mine {
            let label = &p[pat("pass")];
            let pass = &r["passes"][label.as_str()];
            for (col, v) in [
                ("run_index", &r["index"]),
                ("method", &r["method"]),
                ("label", &r["label"]),
                ("seconds_median", &pass["seconds"]["median"]),
                ("seconds_min", &pass["seconds"]["min"]),
                ("seconds_max", &pass["seconds"]["max"]),
                ("passes", &pass["passes"]),
                ("simd_efficiency", &r["simd"][label.as_str()]["efficiency"]),
                ("simd_subgroups", &r["simd"][label.as_str()]["subgroups"]),
            ] {
                assert!(same(&p[pat(col)], v), "{} {label} {col}: {:?} vs {v}", r["id"], p[pat(col)]);
            }
            share += p[pat("share")].parse::<f64>().unwrap_or(0.0);
        }
        if r["passes"].as_object().unwrap().values().any(|p| p["seconds"]["median"].as_f64() > Some(0.0)) {
            assert!((share - 1.0).abs() < 1e-9, "{}: pass shares add up to {share}", r["id"]);
        }
    }
    assert_eq!(prows.len(), expected_rows);
    (header, rows)
}

#[test]
fn tidy_tables_match_report_json_and_keep_commas_and_quotes() {
    let dir = scratch("tidy");
    let mut config =
        crate::experiment::small_config(serde_json::json!([{"method": "cpu"}, {"method": "megakernel"}]));
    // Every GPU run fails, on any machine, with an error that quotes this name (escaped, as Rust
    // debug-prints it): a string with commas and quotes for the CSV to carry.
    let adapter = "no, \"such\"\nadapter";
    config["adapter"] = Value::String(adapter.into());
    let path = write_config(&dir, "tidy", &config);
    let out = dir.join("out");
    let o = crate::experiment::run_experiment(&path, &out, &dir.join("cache"));
    assert!(!o.status.success());
    assert_valid(&out);
    let (header, rows) = assert_tidy(&out);
    let errors: Vec<&String> =
        rows.iter().map(|r| &r[header.iter().position(|h| h == "error").unwrap()]).collect();
    // (The error may quote the name escaped; either way it holds commas and quotes.)
    assert_eq!(errors.iter().filter(|e| e.contains(',') && e.contains('"')).count(), 2, "{errors:?}");
    // The knob columns are there whatever the methods, in a stable order.
    let knobs: Vec<&str> =
        ["workgroup_size", "samples_per_dispatch", "pool_size", "compaction", "shade"].into();
    let found: Vec<&str> = header.iter().map(String::as_str).filter(|h| knobs.contains(h)).collect();
    assert_eq!(found, knobs);

    // `experiment report` rewrites them from report.json.
    std::fs::remove_file(out.join("runs.csv")).unwrap();
    std::fs::remove_file(out.join("passes.csv")).unwrap();
    let o = wavetrace(&["experiment", "report", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(assert_tidy(&out).1, rows);
}
