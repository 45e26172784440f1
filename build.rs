//! Composes the entry shaders `src/gpu/shader_variants.rs` lists, in the variants it lists (a
//! variant swaps hook files for others: subgroup counters for the no-op instrumentation,
//! subgroup-aggregated atomics for per-lane ones, a subgroup scan), with their includes, and
//! validates each with naga, so a shader error is a build error. Writes the composed sources to
//! OUT_DIR and `shaders.rs`, the constants `src/gpu/shaders.rs` embeds them with: exactly the
//! variants listed are composed, validated and embedded. A `.wgsl` file under `shaders/` that no
//! variant reads is an error, so an entry cannot be left out of the list unvalidated.

#[path = "src/shader_include.rs"]
mod shader_include;
#[path = "src/gpu/shader_variants.rs"]
mod shader_variants;

use shader_variants::{Hook, ENTRIES};
use std::cell::RefCell;
use std::collections::BTreeSet;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

fn main() {
    git_commit();
    let root = Path::new("shaders");
    let out = PathBuf::from(std::env::var("OUT_DIR").unwrap());
    println!("cargo:rerun-if-changed=shaders");
    println!("cargo:rerun-if-changed=src/shader_include.rs");
    println!("cargo:rerun-if-changed=src/gpu/shader_variants.rs");
    // Variants an earlier list had must not linger (gpu::shaders' test compares the directory).
    for e in std::fs::read_dir(&out).expect("read OUT_DIR").flatten() {
        if e.path().extension().is_some_and(|x| x == "wgsl") {
            std::fs::remove_file(e.path()).unwrap();
        }
    }
    let read_files = RefCell::new(BTreeSet::new());
    let mut consts = String::from("// Written by build.rs from src/gpu/shader_variants.rs.\n");
    let mut failed = false;
    for entry in ENTRIES {
        let mut sources = Vec::new();
        for hooks in entry.variants() {
            let read = |p: &Path| {
                let mut p = p.to_path_buf();
                for &(file, swap) in hooks.iter().flat_map(|h| h.swaps()) {
                    if p == root.join(file) {
                        p = root.join(swap);
                    }
                }
                read_files.borrow_mut().insert(p.clone());
                // Entry points hand their subgroup width to `instrument_begin` (instrument.wgsl).
                std::fs::read_to_string(&p).map_err(|e| e.to_string()).map(|s| {
                    if hooks.contains(&Hook::Instrument) {
                        s.replace("/*@subgroup_size_param*/", "@builtin(subgroup_size) instrument_width: u32")
                            .replace("/*@subgroup_size_arg*/", "instrument_width")
                    } else {
                        s
                    }
                })
            };
            let name = entry.composed_name(&hooks);
            // naga 30 takes subgroup builtins without `enable subgroups;` (which it rejects).
            let (src, files) = match shader_include::compose(root, entry.file, &read) {
                Ok(x) => x,
                Err(e) => {
                    println!("cargo:warning=shader {}: {e}", entry.file);
                    failed = true;
                    break;
                }
            };
            for f in &files {
                println!("cargo:rerun-if-changed=shaders/{f}");
            }
            // A hook the entry never includes would make a variant that is the plain one.
            for h in &hooks {
                let hook_file = h.swaps()[0].0;
                if !files.iter().any(|f| f == hook_file) {
                    println!(
                        "cargo:warning=shader {}: lists hook {h:?} but never includes {hook_file}",
                        entry.file
                    );
                    failed = true;
                }
            }
            if let Err(e) = validate(&src) {
                println!("cargo:warning=shader {name} is invalid:");
                for line in e.lines() {
                    println!("cargo:warning={line}");
                }
                failed = true;
            }
            std::fs::write(out.join(&name), src).unwrap();
            sources.push(format!("include_str!(concat!(env!(\"OUT_DIR\"), \"/{name}\"))"));
        }
        if entry.hooks.is_empty() {
            writeln!(consts, "pub const {}: &str = {};", entry.name, sources[0]).unwrap();
        } else {
            let hooks: Vec<String> = entry.hooks.iter().map(|h| format!("Hook::{h:?}")).collect();
            writeln!(
                consts,
                "pub const {}: Shader = Shader {{ file: {:?}, hooks: &[{}], variants: &[{}] }};",
                entry.name,
                entry.file,
                hooks.join(", "),
                sources.join(", ")
            )
            .unwrap();
        }
    }
    // Every shader file is an entry, included by one, or swapped in by a variant.
    let read_files = read_files.into_inner();
    for file in wgsl_files(root) {
        if !read_files.contains(&file) {
            println!(
                "cargo:warning={}: no variant in src/gpu/shader_variants.rs reads it (an entry left out?)",
                file.display()
            );
            failed = true;
        }
    }
    if failed {
        panic!("WGSL shaders failed to compose or validate (see warnings above)");
    }
    std::fs::write(out.join("shaders.rs"), consts).unwrap();
}

/// Every `.wgsl` file under `dir`, as `dir/...`.
fn wgsl_files(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    for e in std::fs::read_dir(dir).expect("read shaders/").flatten() {
        let p = e.path();
        if p.is_dir() {
            out.extend(wgsl_files(&p));
        } else if p.extension().is_some_and(|x| x == "wgsl") {
            out.push(p);
        }
    }
    out
}

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
        // The branch's file by git's own path: in a linked worktree the refs live in the common
        // directory, not in `--git-dir` (a path that does not exist reruns this on every build).
        if let Some(head_ref) = git(&["symbolic-ref", "-q", "HEAD"]) {
            let path =
                git(&["rev-parse", "--git-path", &head_ref]).unwrap_or_else(|| format!("{dir}/{head_ref}"));
            println!("cargo:rerun-if-changed={path}");
        }
    }
}
