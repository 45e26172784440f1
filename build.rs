//! Composes every entry shader (`shaders/*.wgsl`, `shaders/{tests,wavefront}/*.wgsl`) with its
//! includes and validates it with naga, so a shader error is a build error. Shaders that include
//! the `shared/instrument.wgsl` hook get an `.instrumented` variant with subgroup counters, and
//! those that include `shared/append.wgsl` a `.subgroup` variant with subgroup-aggregated queue
//! appends (and `.instrumented.subgroup` with both). The composed sources land in OUT_DIR and
//! are embedded by `src/gpu/shaders.rs`.

#[path = "src/shader_include.rs"]
mod shader_include;

use std::path::{Path, PathBuf};

fn main() {
    git_commit();
    let root = Path::new("shaders");
    let out = PathBuf::from(std::env::var("OUT_DIR").unwrap());
    println!("cargo:rerun-if-changed=shaders");
    println!("cargo:rerun-if-changed=src/shader_include.rs");
    let mut entries = Vec::new();
    for dir in ["", "tests", "wavefront"] {
        for e in std::fs::read_dir(root.join(dir)).expect("read shaders/") {
            let p = e.unwrap().path();
            if p.extension().is_some_and(|x| x == "wgsl") {
                entries.push(p.strip_prefix(root).unwrap().to_string_lossy().into_owned());
            }
        }
    }
    entries.sort();
    let mut failed = false;
    for entry in &entries {
        let name = entry.trim_end_matches(".wgsl").replace('/', "_");
        // A variant swaps hooks: the `--instrument` variant the no-op instrument hook for
        // subgroup counters, the `.subgroup` variant per-lane queue appends for subgroup-aggregated
        // ones (`--append`). A variant is written only where the entry includes every hook it
        // swaps.
        let variants: [(&str, &[Hook]); 4] = [
            ("", &[]),
            (".instrumented", &[INSTRUMENT]),
            (".subgroup", &[APPEND]),
            (".instrumented.subgroup", &[INSTRUMENT, APPEND]),
        ];
        for (suffix, hooks) in variants {
            let read = |p: &Path| {
                let mut p = p.to_path_buf();
                for h in hooks.iter() {
                    if p.ends_with(h.file) {
                        p = root.join(h.swap);
                    }
                    // The coherence counters ride on the instrument variant, where included.
                    if h.file == INSTRUMENT.file && p.ends_with(COHERENCE.file) {
                        p = root.join(COHERENCE.swap);
                    }
                }
                // Entry points hand their subgroup width to `instrument_begin` (instrument.wgsl).
                std::fs::read_to_string(&p).map_err(|e| e.to_string()).map(|s| {
                    if hooks.iter().any(|h| h.file == INSTRUMENT.file) {
                        s.replace("/*@subgroup_size_param*/", "@builtin(subgroup_size) instrument_width: u32")
                            .replace("/*@subgroup_size_arg*/", "instrument_width")
                    } else {
                        s
                    }
                })
            };
            // naga 30 takes subgroup builtins without `enable subgroups;` (which it rejects).
            let (src, files) = match shader_include::compose(root, entry, &read) {
                Ok(x) => x,
                Err(e) => {
                    println!("cargo:warning=shader {entry}: {e}");
                    failed = true;
                    break;
                }
            };
            for f in &files {
                println!("cargo:rerun-if-changed=shaders/{f}");
            }
            if !hooks.iter().all(|h| files.iter().any(|f| f == h.file)) {
                continue; // a hook it lacks: no such variant
            }
            if let Err(e) = validate(&src) {
                println!("cargo:warning=shader {entry}{suffix} is invalid:");
                for line in e.lines() {
                    println!("cargo:warning={line}");
                }
                failed = true;
            }
            std::fs::write(out.join(format!("{name}{suffix}.wgsl")), src).unwrap();
        }
    }
    if failed {
        panic!("WGSL shaders failed to compose or validate (see warnings above)");
    }
}

/// A shared file that a variant replaces with another.
struct Hook {
    file: &'static str,
    swap: &'static str,
}

const INSTRUMENT: Hook = Hook { file: "shared/instrument.wgsl", swap: "shared/instrument_on.wgsl" };
const COHERENCE: Hook = Hook { file: "shared/coherence.wgsl", swap: "shared/coherence_on.wgsl" };
const APPEND: Hook = Hook { file: "shared/append.wgsl", swap: "shared/append_subgroup.wgsl" };

fn validate(src: &str) -> Result<(), String> {
    let module = naga::front::wgsl::parse_str(src).map_err(|e| e.emit_to_string(src))?;
    let mut v =
        naga::valid::Validator::new(naga::valid::ValidationFlags::all(), naga::valid::Capabilities::all());
    v.validate(&module).map_err(|e| e.emit_to_string(src))?;
    Ok(())
}

/// The commit the binary is built from, for reports (`WAVETRACE_GIT_COMMIT`; "unknown" outside
/// a git checkout), with "-dirty" when tracked files differ from it. Rebuilt when HEAD or the
/// index moves, so a report never names a commit whose code it did not run.
fn git_commit() {
    let git = |args: &[&str]| {
        std::process::Command::new("git")
            .args(args)
            .output()
            .ok()
            .filter(|o| o.status.success())
            .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
    };
    let mut commit = git(&["rev-parse", "HEAD"]).unwrap_or_else(|| "unknown".into());
    // --no-optional-locks: a plain `git status` refreshes the index it reads, and the index is
    // watched below, so every build would re-run this script and recompile the crate.
    let status = git(&["--no-optional-locks", "status", "--porcelain", "--untracked-files=no"]);
    if status.is_some_and(|s| !s.is_empty()) {
        commit.push_str("-dirty");
    }
    println!("cargo:rustc-env=WAVETRACE_GIT_COMMIT={commit}");
    if let Some(dir) = git(&["rev-parse", "--git-dir"]) {
        println!("cargo:rerun-if-changed={dir}/HEAD");
        println!("cargo:rerun-if-changed={dir}/index");
        // Unstaged edits to the binary's sources must flip "-dirty" too.
        println!("cargo:rerun-if-changed=src");
        println!("cargo:rerun-if-changed=Cargo.toml");
        if let Some(head_ref) = git(&["symbolic-ref", "-q", "HEAD"]) {
            println!("cargo:rerun-if-changed={dir}/{head_ref}");
        }
    }
}
