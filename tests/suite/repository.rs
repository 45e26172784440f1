//! The repository itself: small enough to travel to a GPU machine. The device tool sends the
//! whole working tree (tracked files and carried binaries, 64 MiB at most); the tracked part is
//! kept under 24 MiB so that the binaries (the release wavetrace is about 18 MB), the Vulkan
//! loader and new results fit beside it (scripts/device_dry_run.sh checks the whole of what
//! travels against the 64 MiB).

use std::process::Command;

/// Most bytes the tracked tree may hold.
const TRACKED_LIMIT: u64 = 24 * 1024 * 1024;

#[test]
fn tracked_tree_fits_the_device_run() {
    let root = crate::common::root();
    let out = Command::new("git")
        .args(["ls-files", "-z"])
        .current_dir(&root)
        .output()
        .expect("git ls-files: the tests run in a git checkout");
    assert!(out.status.success(), "git ls-files: {}", String::from_utf8_lossy(&out.stderr));
    let mut total = 0;
    let mut largest = Vec::new();
    for name in out.stdout.split(|&b| b == 0).filter(|n| !n.is_empty()) {
        let name = String::from_utf8_lossy(name).into_owned();
        // A file deleted in the working tree but still in the index travels no more.
        let Ok(meta) = std::fs::metadata(root.join(&name)) else { continue };
        total += meta.len();
        largest.push((meta.len(), name));
    }
    largest.sort_unstable_by(|a, b| b.cmp(a));
    largest.truncate(5);
    assert!(
        total < TRACKED_LIMIT,
        "the tracked tree is {total} bytes, over {TRACKED_LIMIT}: a device run could not carry its \
         binaries beside it. Largest: {largest:?}. Commit compact results (report.json, CSVs, \
         charts), not report.html or images."
    );
    assert!(
        largest.iter().all(|(size, _)| *size < 4 * 1024 * 1024),
        "a tracked file over 4 MiB: {largest:?}"
    );
}
