//! scripts/slurm/: the job scripts are scripts `sbatch` accepts (a `#!` line, every `#SBATCH`
//! directive before the first command), the shard script's body run here with the variables
//! Slurm sets for a two-task array gives two shards that the merge script unites into the
//! report of the whole config, and submit.sh queues the array and then the merge after it.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use serde_json::Value;

fn slurm(name: &str) -> PathBuf {
    crate::common::root().join("scripts/slurm").join(name)
}

fn bash(script: &Path, args: &[&str], env: &[(&str, &str)]) -> Output {
    let mut c = Command::new("bash");
    c.arg(script).args(args).env("WAVETRACE_BIN", crate::common::bin());
    for (k, v) in env {
        c.env(k, v);
    }
    c.output().expect("run bash")
}

fn text(o: &Output) -> String {
    format!("{}{}", String::from_utf8_lossy(&o.stdout), String::from_utf8_lossy(&o.stderr))
}

#[test]
fn job_scripts_are_batch_scripts_with_their_directives_first() {
    for name in ["shard.sbatch", "merge.sbatch"] {
        let script = std::fs::read_to_string(slurm(name)).unwrap();
        assert!(script.starts_with("#!/bin/bash\n"), "{name}: sbatch needs a #! line");
        // sbatch stops reading #SBATCH lines at the first line that is neither a comment nor blank.
        let lines: Vec<&str> = script.lines().collect();
        let first_command = lines.iter().position(|l| !l.trim().is_empty() && !l.starts_with('#')).unwrap();
        let last_directive = lines.iter().rposition(|l| l.starts_with("#SBATCH")).unwrap();
        assert!(last_directive < first_command, "{name}: an #SBATCH line after the first command is ignored");
        assert!(
            script.contains("#SBATCH --open-mode=append"),
            "{name}: a requeued attempt must keep the log"
        );
    }
    let shard = std::fs::read_to_string(slurm("shard.sbatch")).unwrap();
    for needle in ["#SBATCH --array=", "#SBATCH --requeue", "SLURM_ARRAY_TASK_COUNT", "--resume"] {
        assert!(shard.contains(needle), "shard.sbatch lacks {needle}");
    }
}

#[test]
fn shards_run_from_the_array_variables_and_merge_into_the_whole_report() {
    let dir = crate::common::tmp().join("slurm");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let config = dir.join("sweep.json");
    let json = serde_json::json!({
        "schema": "wavetrace-experiment/1",
        "question": "Do the Slurm scripts shard and merge?",
        "scenes": ["three-spheres"],
        "resolutions": ["8x6"],
        "spp": [1, 2, 3],
        "max_depth": [4],
        "repetitions": 1,
        "warmup": 0,
        "methods": [{"method": "cpu"}]
    });
    std::fs::write(&config, json.to_string()).unwrap();
    let shards = dir.join("shards");
    let (cfg, sh) = (config.to_str().unwrap(), shards.to_str().unwrap());
    // An array submitted as --array=3-4: tasks 3 and 4 are shards 0/2 and 1/2.
    for task in ["3", "4"] {
        let env = [
            ("SLURM_ARRAY_TASK_ID", task),
            ("SLURM_ARRAY_TASK_COUNT", "2"),
            ("SLURM_ARRAY_TASK_MIN", "3"),
            ("SLURM_ARRAY_TASK_MAX", "4"),
        ];
        let o = bash(&slurm("shard.sbatch"), &[cfg, sh], &env);
        assert!(o.status.success(), "task {task}: {}", text(&o));
        // A requeued task starts the script again: --resume keeps what it finished.
        let again = bash(&slurm("shard.sbatch"), &[cfg, sh], &env);
        assert!(again.status.success(), "task {task} requeued: {}", text(&again));
    }
    let shard = |i: usize| -> Value {
        serde_json::from_str(&std::fs::read_to_string(shards.join(format!("{i}/report.json"))).unwrap())
            .unwrap()
    };
    let indices = |r: &Value| -> Vec<u64> {
        r["runs"].as_array().unwrap().iter().map(|r| r["index"].as_u64().unwrap()).collect()
    };
    assert_eq!(indices(&shard(0)), vec![0, 2]);
    assert_eq!(indices(&shard(1)), vec![1]);
    assert!(shard(0)["environments"].as_array().unwrap().len() == 2, "the requeued attempt resumed");

    let merged = dir.join("merged");
    let o = bash(&slurm("merge.sbatch"), &[sh, merged.to_str().unwrap()], &[]);
    assert!(o.status.success(), "merge: {}", text(&o));
    let report: Value =
        serde_json::from_str(&std::fs::read_to_string(merged.join("report.json")).unwrap()).unwrap();
    assert_eq!(report["status"], "complete");
    assert_eq!(indices(&report), vec![0, 1, 2]);

    // An array with a step is refused: the shards would not cover the runs.
    let env = [
        ("SLURM_ARRAY_TASK_ID", "0"),
        ("SLURM_ARRAY_TASK_COUNT", "2"),
        ("SLURM_ARRAY_TASK_MIN", "0"),
        ("SLURM_ARRAY_TASK_MAX", "2"),
    ];
    let o = bash(&slurm("shard.sbatch"), &[cfg, sh], &env);
    assert!(!o.status.success() && text(&o).contains("contiguous"), "{}", text(&o));
    // Outside an array task, it says so.
    let o = bash(&slurm("shard.sbatch"), &[cfg, sh], &[]);
    assert!(!o.status.success() && text(&o).contains("not an array task"), "{}", text(&o));
}

#[test]
fn submit_queues_the_array_then_the_merge_after_it() {
    let dir = crate::common::tmp().join("slurm-submit");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    // A stand-in sbatch: records its arguments, answers as `sbatch --parsable` does.
    let log = dir.join("calls");
    let fake = dir.join("sbatch");
    std::fs::write(
        &fake,
        format!("#!/bin/bash\necho \"$*\" >> {}\nif [[ \"$*\" == *shard.sbatch* ]]; then echo '4242;cluster'; else echo 4243; fi\n", log.display()),
    )
    .unwrap();
    let o = bash(
        &slurm("submit.sh"),
        &["experiments/quick.json", "results/quick", "4", "--partition=gpu"],
        &[("SBATCH", &format!("bash {}", fake.display()))],
    );
    assert!(o.status.success(), "{}", text(&o));
    let calls = std::fs::read_to_string(&log).unwrap();
    let calls: Vec<&str> = calls.lines().collect();
    assert_eq!(
        calls,
        [
            "--parsable --array=0-3 --partition=gpu scripts/slurm/shard.sbatch experiments/quick.json results/quick/shards",
            "--parsable --dependency=afterok:4242 --partition=gpu scripts/slurm/merge.sbatch results/quick/shards results/quick/merged",
        ]
    );
    let bad = bash(&slurm("submit.sh"), &["c.json", "out", "0"], &[("SBATCH", "false")]);
    assert!(!bad.status.success() && text(&bad).contains("positive number"), "{}", text(&bad));
}
