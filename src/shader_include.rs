//! The `#include "path"` step that composes WGSL files from `shaders/shared/`. Used by
//! `build.rs` (through `#[path]`), so it depends on std alone. Each file is included once, at
//! its first `#include`; paths are relative to the `shaders/` directory.

use std::collections::HashSet;
use std::path::Path;

/// Composes `entry` (relative to `root`), expanding includes depth-first. `read` loads a file
/// relative to `root`, so tests can compose from memory.
pub fn compose(
    root: &Path,
    entry: &str,
    read: &dyn Fn(&Path) -> Result<String, String>,
) -> Result<(String, Vec<String>), String> {
    let mut out = String::new();
    let mut seen = HashSet::new();
    let mut files = Vec::new();
    expand(root, entry, read, &mut seen, &mut files, &mut Vec::new(), &mut out)?;
    Ok((out, files))
}

fn expand(
    root: &Path,
    file: &str,
    read: &dyn Fn(&Path) -> Result<String, String>,
    seen: &mut HashSet<String>,
    files: &mut Vec<String>,
    chain: &mut Vec<String>,
    out: &mut String,
) -> Result<(), String> {
    if chain.iter().any(|f| f == file) {
        return Err(format!("include cycle: {} -> {file}", chain.join(" -> ")));
    }
    if !seen.insert(file.to_string()) {
        return Ok(());
    }
    files.push(file.to_string());
    let text = read(&root.join(file)).map_err(|e| match chain.last() {
        Some(parent) => format!("{parent}: cannot include {file}: {e}"),
        None => format!("{file}: {e}"),
    })?;
    chain.push(file.to_string());
    out.push_str(&format!("// ---- {file}\n"));
    for (n, line) in text.lines().enumerate() {
        match line.trim().strip_prefix("#include") {
            Some(rest) => {
                let target = rest.trim().strip_prefix('"').and_then(|r| r.strip_suffix('"'));
                let Some(target) = target else {
                    return Err(format!("{file}:{}: expected #include \"path\"", n + 1));
                };
                expand(root, target, read, seen, files, chain, out)?;
            }
            None => {
                out.push_str(line);
                out.push('\n');
            }
        }
    }
    chain.pop();
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashMap;

    fn fs(files: &[(&str, &str)]) -> impl Fn(&Path) -> Result<String, String> {
        let map: HashMap<String, String> =
            files.iter().map(|(k, v)| (format!("r/{k}"), v.to_string())).collect();
        move |p: &Path| map.get(&p.display().to_string()).cloned().ok_or_else(|| "not found".into())
    }

    #[test]
    fn includes_each_file_once_in_first_use_order() {
        let read = fs(&[
            ("main.wgsl", "#include \"a.wgsl\"\n#include \"b.wgsl\"\nfn main() {}"),
            ("a.wgsl", "#include \"c.wgsl\"\nfn a() {}"),
            ("b.wgsl", "#include \"c.wgsl\"\nfn b() {}"),
            ("c.wgsl", "fn c() {}"),
        ]);
        let (src, files) = compose(Path::new("r"), "main.wgsl", &read).unwrap();
        assert_eq!(files, ["main.wgsl", "a.wgsl", "c.wgsl", "b.wgsl"]);
        assert_eq!(src.matches("fn c()").count(), 1);
        assert!(src.find("fn c()").unwrap() < src.find("fn a()").unwrap());
    }

    #[test]
    fn reports_cycles_and_missing_files() {
        let read = fs(&[("a.wgsl", "#include \"b.wgsl\""), ("b.wgsl", "#include \"a.wgsl\"")]);
        let err = compose(Path::new("r"), "a.wgsl", &read).unwrap_err();
        assert!(err.contains("include cycle"), "{err}");
        let read = fs(&[("a.wgsl", "#include \"missing.wgsl\"")]);
        let err = compose(Path::new("r"), "a.wgsl", &read).unwrap_err();
        assert!(err.contains("a.wgsl: cannot include missing.wgsl"), "{err}");
        let read = fs(&[("a.wgsl", "#include missing.wgsl")]);
        assert!(compose(Path::new("r"), "a.wgsl", &read).unwrap_err().contains("a.wgsl:1"));
    }
}
