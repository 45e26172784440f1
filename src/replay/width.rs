//! SIMD widths for the replay (`--simd-width 8,32,64`): powers of two from 1 to 128 lanes.

use anyhow::{bail, Result};

/// The widest subgroup the replay simulates (no GPU has wider; the limit bounds its memory).
pub const MAX_WIDTH: u32 = 128;

/// A width the replay can simulate, or an error that says why not.
pub fn check(w: u32) -> Result<u32> {
    if w == 0 || !w.is_power_of_two() || w > MAX_WIDTH {
        bail!("SIMD width {w}: must be a power of two from 1 to {MAX_WIDTH} lanes (subgroups are 4 to 128 wide on real GPUs)");
    }
    Ok(w)
}

/// A comma-separated list of widths, each checked, in the order given, no repeats.
pub fn parse_list(s: &str) -> Result<Vec<u32>> {
    let mut out = Vec::new();
    for part in s.split(',') {
        let part = part.trim();
        let Ok(w) = part.parse::<u32>() else {
            bail!("SIMD width {part:?}: not a whole number (expected e.g. 8,16,32,64)");
        };
        let w = check(w)?;
        if out.contains(&w) {
            bail!("SIMD width {w} is given twice");
        }
        out.push(w);
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bad_widths_are_refused_with_the_reason() {
        assert_eq!(parse_list("8, 32,64").unwrap(), vec![8, 32, 64]);
        assert_eq!(parse_list("1,128").unwrap(), vec![1, 128]);
        for bad in ["0", "24", "256", "8,x", "", "8,8"] {
            let e = parse_list(bad).unwrap_err().to_string();
            assert!(e.contains("SIMD width"), "{bad}: {e}");
        }
        assert!(check(0).unwrap_err().to_string().contains("power of two"));
        assert!(check(96).is_err() && check(256).is_err());
    }
}
