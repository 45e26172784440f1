//! What is written from a report: `report.json` with its tidy tables (`ExperimentReport::write`,
//! here rather than in `report.rs` so that the report's types do not depend on the tables drawn
//! from them), `charts/*.svg` and `report.html`. Used at the end of a run, by `experiment report`
//! (re-draw) and by `experiment merge`.

use std::path::Path;

use anyhow::{Context, Result};

use super::charts;
use super::html;
use super::report::{ChartRecord, ExperimentReport, REPORT_FILE};
use super::tidy;
use crate::image_io::write_file_atomically;

pub const HTML_FILE: &str = "report.html";

impl ExperimentReport {
    /// Writes `DIR/report.json` atomically (temporary file, then rename), then the tidy tables
    /// drawn from it (`runs.csv`, `passes.csv`), so the three always move together.
    pub fn write(&self, dir: &Path) -> Result<()> {
        let json = serde_json::to_string_pretty(self)?;
        let path = dir.join(REPORT_FILE);
        write_file_atomically(&path, json.as_bytes())
            .with_context(|| format!("writing {}", path.display()))?;
        tidy::write(self, dir)
    }
}

/// Writes the charts and the HTML page for `report` into `dir`, replacing earlier ones, and
/// lists the charts in `report.charts` (the caller writes `report.json`).
pub fn draw(report: &mut ExperimentReport, dir: &Path) -> Result<()> {
    let chart_dir = dir.join("charts");
    std::fs::create_dir_all(&chart_dir).with_context(|| format!("creating {}", chart_dir.display()))?;
    // Charts of an earlier drawing whose data is gone must not linger beside the new ones.
    for entry in std::fs::read_dir(&chart_dir)?.flatten() {
        if entry.path().extension().is_some_and(|e| e == "svg") {
            let _ = std::fs::remove_file(entry.path());
        }
    }
    let drawn = charts::charts(report);
    report.charts.clear();
    for c in &drawn {
        let file = format!("charts/{}.svg", c.stem);
        write_file_atomically(&dir.join(&file), c.svg.as_bytes())?;
        report.charts.push(ChartRecord {
            file,
            title: c.title.clone(),
            kind: c.kind.to_string(),
            scene: c.scene.clone(),
            width: c.width,
            height: c.height,
        });
    }
    let page = html::page(report, &drawn, dir);
    write_file_atomically(&dir.join(HTML_FILE), page.as_bytes())?;
    Ok(())
}

/// `experiment report DIR`: re-draws charts and HTML from `DIR/report.json`.
pub fn redraw(dir: &Path) -> Result<ExperimentReport> {
    let mut report = ExperimentReport::read(dir)?;
    draw(&mut report, dir)?;
    report.write(dir)?;
    Ok(report)
}
