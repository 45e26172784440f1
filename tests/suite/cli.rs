//! The `wavetrace` binary end to end: outputs, reports, and clear errors (never a panic) for bad
//! input.

use crate::common;

use std::path::PathBuf;
use std::process::{Command, Output};

fn wavetrace(args: &[&str]) -> Output {
    Command::new(crate::common::bin()).args(args).output().expect("run wavetrace")
}

fn scratch(name: &str) -> PathBuf {
    let dir = crate::common::tmp().join("cli");
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

/// Runs and expects failure with a message containing every one of `needles`.
fn fails_with(args: &[&str], needles: &[&str]) {
    let out = wavetrace(args);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "{args:?} should fail");
    assert!(!stderr.contains("panicked"), "{args:?} panicked: {stderr}");
    for n in needles {
        assert!(stderr.contains(n), "{args:?}: stderr lacks {n:?}:\n{stderr}");
    }
}

#[test]
fn cpu_render_writes_exr_png_and_report() {
    let (exr, png, json) = (scratch("cpu.exr"), scratch("cpu.png"), scratch("cpu.json"));
    let out = wavetrace(&[
        "render",
        "--scene",
        "three-spheres",
        "--method",
        "cpu",
        "--width",
        "32",
        "--height",
        "18",
        "--spp",
        "4",
        "--out",
        exr.to_str().unwrap(),
        "--png",
        png.to_str().unwrap(),
        "--report",
        json.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let (img, attrs) = wavetrace::image_io::read_exr(&exr).unwrap();
    assert_eq!((img.width, img.height), (32, 18));
    let attr = |k: &str| attrs.iter().find(|(n, _)| n == k).map(|(_, v)| v.clone());
    assert_eq!(attr("wavetrace.method").as_deref(), Some("cpu"));
    assert_eq!(attr("wavetrace.spp").as_deref(), Some("4"));
    assert_eq!(attr("wavetrace.scene").as_deref(), Some("three-spheres"));
    assert!(attr("wavetrace.render_time_s").is_some());
    // The PNG is the EXR's sRGB preview, byte for byte (not merely a non-empty file).
    let (width, height, preview) = wavetrace::image_io::read_png_rgb8(&png).unwrap();
    assert_eq!((width, height), (32, 18));
    let want: Vec<u8> = img.data.iter().map(|&v| wavetrace::image_io::linear_to_srgb8(v)).collect();
    assert_eq!(preview, want, "PNG pixels are the EXR's, sRGB-encoded");
    let report: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    assert_eq!(report["schema"], "wavetrace-run/1");
    assert_eq!(report["method"], "cpu");
    assert_eq!(report["samples"], 32 * 18 * 4);
    assert_eq!(report["invalid_samples"], 0);
    assert!(report["samples_per_second"].as_f64().unwrap() > 0.0);
    assert!(report["build"]["git_commit"].is_string());
    assert!(report["machine"]["logical_cores"].as_u64().unwrap() >= 1);
    // The EXR's mean is the report's image mean.
    let m = img.mean();
    let mean = (m[0] + m[1] + m[2]) / 3.0;
    assert!((mean - report["image_mean"].as_f64().unwrap()).abs() < 1e-5);
}

#[test]
fn gpu_report_names_adapter_and_timing_source() {
    let Some(ctx) = common::gpu() else { return };
    let (exr, json) = (scratch("mk.exr"), scratch("mk.json"));
    let out = wavetrace(&[
        "render",
        "--scene",
        "furnace",
        "--method",
        "megakernel",
        "--width",
        "16",
        "--height",
        "16",
        "--spp",
        "2",
        "--out",
        exr.to_str().unwrap(),
        "--report",
        json.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let report: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    assert_eq!(report["adapter"]["name"], ctx.summary.name.as_str(), "the adapter the run used");
    assert_eq!(report["samples"], 16 * 16 * 2);
    assert_eq!(report["invalid_samples"], 0);
    assert!(report["adapter"]["backend"].is_string());
    assert!(report["adapter"]["driver"].is_string());
    assert!(["timestamps", "wall-clock"].contains(&report["time_source"].as_str().unwrap()));
    assert!(report["passes"]["megakernel"]["passes"].as_u64().unwrap() >= 1);
    assert!(report["passes"]["accumulate"]["passes"].as_u64().unwrap() >= 1);
    assert!(report["gpu_seconds"].as_f64().unwrap() > 0.0);
}

#[test]
fn exported_scene_renders_like_the_builtin() {
    let out = wavetrace(&["scene", "export", "three-spheres"]);
    assert!(out.status.success());
    let file = scratch("three.json");
    std::fs::write(&file, &out.stdout).unwrap();
    let render = |scene: &str, name: &str| {
        let exr = scratch(name);
        let o = wavetrace(&[
            "render",
            "--scene",
            scene,
            "--method",
            "cpu",
            "--width",
            "16",
            "--height",
            "9",
            "--spp",
            "2",
            "--out",
            exr.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        wavetrace::image_io::read_exr(&exr).unwrap().0
    };
    assert_eq!(render("three-spheres", "a.exr").data, render(file.to_str().unwrap(), "b.exr").data);
}

#[test]
fn bad_input_gives_clear_errors() {
    let out = scratch("x.exr");
    let out = out.to_str().unwrap();
    // A name that is neither built-in nor a file lists the built-ins, as experiment configs do.
    fails_with(
        &["render", "--scene", "no-such-scene", "--out", out],
        &["no-such-scene", "neither a built-in scene nor a file", "\"rtiow-final\"", "\"cornell\""],
    );
    fails_with(&["render", "--scene", "cornel", "--out", out], &["did you mean \"cornell\""]);
    let bad = scratch("bad.json");
    std::fs::write(&bad, "{\"format\": \"wavetrace-scene/1\",\n \"camera\": [}").unwrap();
    fails_with(
        &["render", "--scene", bad.to_str().unwrap(), "--method", "cpu", "--out", out],
        &["bad.json", "line 2"],
    );
    let radius = crate::common::root().join("tests/scenes/bad-radius.json");
    fails_with(
        &["render", "--scene", radius.to_str().unwrap(), "--method", "cpu", "--out", out],
        &["bad-radius.json", "radius"],
    );
    fails_with(&["render", "--scene", "furnace", "--spp", "0", "--method", "cpu", "--out", out], &["spp"]);
    fails_with(
        &["render", "--scene", "furnace", "--width", "0", "--method", "cpu", "--out", out],
        &["empty"],
    );
    fails_with(&["scene", "export", "nope"], &["nope", "rtiow-final"]);
    let unwritable = "/nonexistent-dir/x.exr";
    fails_with(
        &[
            "render", "--scene", "furnace", "--method", "cpu", "--width", "8", "--height", "8", "--out",
            unwritable,
        ],
        &["nonexistent-dir"],
    );
    if common::gpu().is_some() {
        fails_with(
            &[
                "render",
                "--scene",
                "furnace",
                "--method",
                "megakernel",
                "--adapter",
                "no-such-gpu",
                "--out",
                out,
            ],
            &["no-such-gpu"],
        );
        fails_with(
            &[
                "render",
                "--scene",
                "furnace",
                "--method",
                "megakernel",
                "--workgroup-size",
                "0",
                "--out",
                out,
            ],
            &["--workgroup-size must be in 1..=1024, got 0"],
        );
    }
}

#[test]
fn help_shows_examples() {
    let out = wavetrace(&["render", "--help"]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("Examples:") && text.contains("--scene rtiow-final"));
    let out = wavetrace(&["--help"]);
    assert!(String::from_utf8_lossy(&out.stdout).contains("wavetrace scene export"));
}

/// `render -h` shows the options most renders need, under 60 lines; `--help` shows every option,
/// grouped by what it tunes, with no internal names (issue 45).
#[test]
fn render_help_is_short_and_grouped() {
    let short = String::from_utf8_lossy(&wavetrace(&["render", "-h"]).stdout).into_owned();
    assert!(short.lines().count() < 60, "{} lines:\n{short}", short.lines().count());
    let option_line = |o: &str| short.lines().any(|l| l.trim_start().starts_with(o));
    assert!(option_line("--spp") && option_line("--out") && !option_line("--pool-size"), "{short}");
    assert!(short.contains("--help"), "says where the rest is: {short}");
    let long = String::from_utf8_lossy(&wavetrace(&["render", "--help"]).stdout).into_owned();
    let heading = |h: &str| long.lines().position(|l| l == h).unwrap_or_else(|| panic!("no {h:?}"));
    let option = |o: &str| {
        long.lines().position(|l| l.trim_start().starts_with(o)).unwrap_or_else(|| panic!("no {o}"))
    };
    for (h, o) in [
        ("Wavefront:", "--pool-size"),
        ("Megakernel:", "--threads"),
        ("GPU methods:", "--preheat"),
        ("Lights (with --nee on):", "--light-select"),
        ("Numerics and stress:", "--ray-offset"),
    ] {
        assert!(heading(h) < option(o), "{o} under {h}");
    }
    for leak in ["crate::", "AUTO_SLOT_POOLS", "the library's", "ShaderRuntimeChecks"] {
        assert!(!long.contains(leak), "internal name {leak:?} in render --help");
    }
}

#[test]
fn wavefront_cli_reports_passes_histogram_and_simd() {
    let Some(ctx) = common::gpu() else { return };
    let (exr, json) = (scratch("wf.exr"), scratch("wf.json"));
    let out = wavetrace(&[
        "render",
        "--scene",
        "three-spheres",
        "--method",
        "wavefront",
        "--schedule",
        "waves",
        "--width",
        "24",
        "--height",
        "16",
        "--spp",
        "2",
        "--compaction-method",
        "scan",
        "--shade",
        "single",
        "--pool-size",
        "500",
        "--instrument",
        "--out",
        exr.to_str().unwrap(),
        "--report",
        json.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        stdout.contains("compact_scan") && stdout.contains("bounce"),
        "pass table and histogram:\n{stdout}"
    );
    let r: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    assert_eq!(r["method"], "wavefront");
    assert_eq!(r["pool_size"], 500);
    assert_eq!(r["options"]["wavefront"]["compaction"], "scan");
    assert_eq!(r["options"]["wavefront"]["shade"], "single");
    assert!(r["bytes_per_path"].as_u64().unwrap() > 0);
    assert_eq!(r["passes_per_bounce"]["intersect"].as_array().unwrap().len(), 50);
    assert_eq!(r["queue_histogram"]["rays"][0], 24 * 16 * 2);
    assert!(r["indirect_validation"].is_boolean());
    if ctx.summary.subgroups {
        let e = r["simd"]["shade"]["efficiency"].as_f64().unwrap();
        assert!(e > 0.0 && e <= 1.0);
    } else {
        common::skipped(
            "cli::wavefront_cli_reports_passes_histogram_and_simd: simd",
            "no subgroup operations",
        );
    }
}

#[test]
fn compare_reports_metrics_and_refuses_mismatched_sizes() {
    let render = |name: &str, spp: &str, w: &str| {
        let exr = scratch(name);
        let o = wavetrace(&[
            "render",
            "--scene",
            "three-spheres",
            "--method",
            "cpu",
            "--width",
            w,
            "--height",
            "9",
            "--spp",
            spp,
            "--out",
            exr.to_str().unwrap(),
        ]);
        assert!(o.status.success());
        exr
    };
    let (a, b, c) = (render("c1.exr", "2", "16"), render("c2.exr", "32", "16"), render("c3.exr", "2", "8"));
    let out = wavetrace(&["compare", a.to_str().unwrap(), b.to_str().unwrap(), "--json"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let r: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let relmse = r["metrics"]["relmse"].as_f64().unwrap();
    assert!(relmse > 0.0 && relmse.is_finite());
    let same = wavetrace(&["compare", a.to_str().unwrap(), a.to_str().unwrap(), "--json"]);
    let r: serde_json::Value = serde_json::from_slice(&same.stdout).unwrap();
    assert_eq!(r["metrics"]["mse"], 0.0);
    fails_with(&["compare", a.to_str().unwrap(), c.to_str().unwrap()], &["16x9", "8x9"]);
}

/// Servers, containers and batch jobs have no `XDG_RUNTIME_DIR`: a GPU run there must not print
/// the Vulkan device-selection layer's complaint about it (`gpu::headless`).
#[test]
fn gpu_runs_are_quiet_without_a_runtime_dir() {
    if common::gpu().is_none() {
        return;
    }
    let exr = scratch("headless.exr");
    for args in [
        &["info"][..],
        &[
            "render",
            "--scene",
            "furnace",
            "--method",
            "megakernel",
            "--width",
            "8",
            "--height",
            "8",
            "--spp",
            "1",
            "--out",
            exr.to_str().unwrap(),
        ],
    ] {
        let out = Command::new(crate::common::bin())
            .args(args)
            .env_remove("XDG_RUNTIME_DIR")
            .env_remove("NODEVICE_SELECT")
            .output()
            .expect("run wavetrace");
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success(), "{args:?}: {stderr}");
        assert!(!stderr.contains("XDG_RUNTIME_DIR"), "{args:?} printed:\n{stderr}");
    }
}

/// `scripts/device_figures.sh` (the GPU figures in bounded steps, for a machine without a
/// toolchain) runs a step on the software driver at tiny size and leaves one archive of compact
/// results in its output folder, with the adapter it checked; it refuses a step it does not
/// know, more steps than the device tool returns files for, and a software adapter unless told.
/// The whole device procedure (the copy that travels, every step, the tool's limits) is
/// rehearsed by scripts/device_dry_run.sh, which CI runs.
#[test]
fn device_figures_script_runs_a_step_and_packs_it() {
    if common::gpu().is_none() {
        return;
    }
    let root = crate::common::root();
    let out = scratch("device_figures");
    let _ = std::fs::remove_dir_all(&out);
    let script = |args: &[&str], allow_software: bool| {
        Command::new("bash")
            .arg(root.join("scripts/device_figures.sh"))
            .args(args)
            .env("WAVETRACE_BIN", crate::common::bin())
            .env("WAVETRACE_DEVICE_WORK", out.join("work"))
            .env("WAVETRACE_DEVICE_ALLOW_SOFTWARE", if allow_software { "1" } else { "0" })
            .output()
            .expect("run device_figures.sh")
    };
    let o = out.to_str().unwrap();
    let run = script(&["--scale", "tiny", "--out", o, "headline"], true);
    let log = std::fs::read_to_string(out.join("device.log")).unwrap_or_default();
    assert!(run.status.success(), "{}\n{log}", String::from_utf8_lossy(&run.stderr));
    assert!(log.contains("adapter: ") && log.contains("backend Vulkan"), "{log}");
    let files: Vec<String> = std::fs::read_dir(&out)
        .unwrap()
        .flatten()
        .filter(|e| e.path().is_file())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    assert!(files.contains(&"headline.tar.gz".to_string()), "{files:?}");
    let listing = Command::new("tar").arg("-tzf").arg(out.join("headline.tar.gz")).output().unwrap();
    let listing = String::from_utf8_lossy(&listing.stdout);
    for want in ["./report.json", "./runs.csv", "./passes.csv", "./step.log", "./info.txt"] {
        assert!(listing.lines().any(|l| l == want), "{want} not in the archive:\n{listing}");
    }
    assert!(!listing.contains(".exr") && !listing.contains(".png"), "images travel back:\n{listing}");
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("work/headline/report.json")).unwrap())
            .unwrap();
    assert_eq!(report["status"], "complete");
    assert_eq!(report["runs"].as_array().unwrap().len(), 20, "2 scenes × 2 spp × 5 methods");

    let refused = |args: &[&str], allow: bool, expected: &str| {
        let r = script(args, allow);
        let text = format!(
            "{}{}{}",
            String::from_utf8_lossy(&r.stdout),
            String::from_utf8_lossy(&r.stderr),
            std::fs::read_to_string(out.join("device.log")).unwrap_or_default()
        );
        assert!(!r.status.success() && text.contains(expected), "{args:?}: {text}");
    };
    refused(&["--out", o, "nonsense"], true, "unknown step 'nonsense'");
    // Seven steps: seven archives, the log and info.txt would be nine files; the tool returns 8.
    let seven = ["tests", "headline", "simd", "regeneration", "baselines", "seeds", "pool"];
    refused(&[&["--out", o][..], &seven[..]].concat(), true, "at most 6 steps");
    refused(&["--out", o, "--scale", "tiny", "headline"], false, "not a discrete GPU");
}

/// `--light-sampling` and `--light-select` reach the run record and the EXR's attributes; a value
/// that is neither is refused naming the choices.
#[test]
fn light_knobs_reach_the_report_and_the_exr() {
    let (exr, json) = (scratch("lights.exr"), scratch("lights.json"));
    let out = wavetrace(&[
        "render",
        "--scene",
        "two-lights",
        "--method",
        "cpu",
        "--nee",
        "on",
        "--light-sampling",
        "area",
        "--light-select",
        "uniform",
        "--width",
        "16",
        "--height",
        "12",
        "--spp",
        "2",
        "--out",
        exr.to_str().unwrap(),
        "--report",
        json.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let report: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    assert_eq!(report["options"]["light_sampling"], "area");
    assert_eq!(report["options"]["light_select"], "uniform");
    let (_, attrs) = wavetrace::image_io::read_exr(&exr).unwrap();
    let attr = |k: &str| attrs.iter().find(|(n, _)| n == k).map(|(_, v)| v.clone());
    assert_eq!(attr("wavetrace.light_sampling").as_deref(), Some("area"));
    assert_eq!(attr("wavetrace.light_select").as_deref(), Some("uniform"));
    fails_with(
        &["render", "--scene", "two-lights", "--light-sampling", "cone", "--out", "x.exr"],
        &["cone", "area", "solid-angle"],
    );
}

/// On an OpenGL adapter (`WGPU_BACKEND=gl`) the wavefront's layouts exceed GL's storage-buffer
/// count: the error must say so and name the fix, not "PipelineLayout is invalid". Machines
/// without a GL adapter have nothing to check.
#[test]
fn wavefront_on_an_opengl_adapter_says_why_it_cannot_run() {
    let out = Command::new(crate::common::bin())
        .args(["render", "--scene", "three-spheres", "--method", "wavefront", "--width", "16"])
        .args(["--height", "8", "--spp", "1", "--out", scratch("gl.exr").to_str().unwrap()])
        .env("WGPU_BACKEND", "gl")
        .output()
        .expect("run wavetrace");
    let stderr = String::from_utf8_lossy(&out.stderr);
    if stderr.contains("no GPU adapter") {
        eprintln!("no OpenGL adapter here: {stderr}");
        return;
    }
    assert!(!stderr.contains("panicked"), "{stderr}");
    if out.status.success() {
        // A GL driver with enough storage buffers runs it: nothing to refuse.
        return;
    }
    assert!(stderr.contains("mesa-vulkan-drivers"), "{stderr}");
    assert!(stderr.contains("does not fit"), "{stderr}");
}

/// Every option text, every subcommand's description and every value's help is written for
/// users: no issue numbers and no experiment config file names (those belong in the docs), and
/// no environment variable shown with an empty value.
#[test]
fn help_texts_name_no_issues_or_config_files() {
    fn walk(c: &clap::Command, path: String, texts: &mut Vec<(String, String)>) {
        let mut push = |what: String, t: Option<&clap::builder::StyledStr>| {
            if let Some(t) = t {
                texts.push((what, t.to_string()));
            }
        };
        push(format!("{path} about"), c.get_about());
        push(format!("{path} long about"), c.get_long_about());
        for a in c.get_arguments() {
            let name = format!("{path} --{}", a.get_long().unwrap_or(a.get_id().as_str()));
            push(name.clone(), a.get_help());
            push(name.clone(), a.get_long_help());
            for v in a.get_possible_values() {
                push(format!("{name} {}", v.get_name()), v.get_help());
            }
        }
        for s in c.get_subcommands() {
            walk(s, format!("{path} {}", s.get_name()), texts);
        }
    }
    let mut texts = Vec::new();
    walk(&wavetrace::cli::command(), "wavetrace".into(), &mut texts);
    let experiments = crate::common::root().join("experiments");
    let mut leaks = Vec::new();
    for (what, text) in &texts {
        let words: Vec<&str> = text.split(|c: char| c.is_whitespace() || "(),;:`".contains(c)).collect();
        for (i, w) in words.iter().enumerate() {
            let issue =
                w.eq_ignore_ascii_case("issue") && words.get(i + 1).is_some_and(|n| n.parse::<u32>().is_ok());
            let stem = w.trim_end_matches('.').rsplit('/').next().unwrap_or("");
            let config = stem.ends_with(".json") && experiments.join(stem).is_file();
            if issue || config || w.starts_with("experiments/") {
                leaks.push(format!("{what}: {w:?} in {text:?}"));
            }
        }
    }
    assert!(texts.len() > 100, "the walk found the options: {}", texts.len());
    assert!(leaks.is_empty(), "{}", leaks.join("\n"));
    let run = String::from_utf8_lossy(&wavetrace(&["experiment", "run", "--help"]).stdout).into_owned();
    assert!(run.contains("[env: WAVETRACE_CACHE]") && !run.contains("WAVETRACE_CACHE=]"), "{run}");
}

/// `render -h` names every group of options it hides, with every flag in it, and says how to
/// see them; so every flag its examples use is named on it.
#[test]
fn render_short_help_names_every_hidden_group_and_flag() {
    let short = String::from_utf8_lossy(&wavetrace(&["render", "-h"]).stdout).into_owned();
    let cmd = wavetrace::cli::command();
    let render = cmd.find_subcommand("render").unwrap();
    for a in render.get_arguments().filter(|a| a.get_long().is_some() && !a.is_hide_set()) {
        let flag = format!("--{}", a.get_long().unwrap());
        let named = short.split(|c: char| c.is_whitespace() || c == ',').any(|w| w == flag);
        assert!(named, "{flag} is not on render -h:\n{short}");
        if let Some(h) = a.get_help_heading() {
            assert!(short.contains(&format!("  {h}:")), "group {h:?} is not named:\n{short}");
        }
    }
    assert!(short.contains("wavetrace render --help` shows them all"), "{short}");
}

/// Errors that point to the fix: `--set` into a misspelt field suggests the right one; a
/// missing scene file is named by the path it was resolved to (relative to the config in a
/// config), and a name that is clearly a path does not list the built-in scenes.
#[test]
fn errors_point_to_the_fix() {
    let dir = scratch("errors-fix");
    std::fs::create_dir_all(&dir).unwrap();
    let config = dir.join("c.json");
    std::fs::copy(crate::common::root().join("experiments/quick.json"), &config).unwrap();
    let c = config.to_str().unwrap();
    fails_with(
        &["experiment", "run", c, "--list", "--set", "method.1.schedule=waves"],
        &["did you mean \"methods\"?"],
    );
    let resolved = std::path::absolute(dir.join("scenes/missing.json")).unwrap();
    let out = wavetrace(&["experiment", "run", c, "--list", "--set", "scenes=[\"scenes/missing.json\"]"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success() && stderr.contains(&format!("{} does not exist", resolved.display())),
        "{stderr}"
    );
    assert!(stderr.contains("relative to the config") && !stderr.contains("\"cornell\""), "{stderr}");
    let out = wavetrace(&["render", "--scene", "nope/missing.json", "--out", "x.exr"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && stderr.contains("no such scene file"), "{stderr}");
    assert!(!stderr.contains("built-in") && stderr.lines().count() == 1, "short: {stderr}");
}
