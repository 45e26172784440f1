use wavetrace::chart::*;
#[test]
fn dump() {
    let d = std::path::Path::new("/tmp/chartwork/out");
    std::fs::create_dir_all(d).unwrap();
    let s = |n: &str, p: Vec<(f64, f64)>| Series { name: n.into(), points: p };
    let pools: Vec<f64> = (10..=22).step_by(2).map(|e| 2f64.powi(e)).collect();
    let line = LineChart {
        title: "Frame time vs pool size (rtiow-final, 16 spp)".into(),
        x_label: "pool size (paths)".into(),
        y_label: "frame time (ms)".into(),
        x_log: true,
        y_log: false,
        series: vec![
            s("megakernel", pools.iter().map(|&p| (p, 41.0)).collect()),
            s("wavefront, compaction", pools.iter().map(|&p| (p, 30.0 + 2e5 / p)).collect()),
            s("wavefront, no compaction <&>", pools.iter().map(|&p| (p, 35.0 + 1e5 / p)).collect()),
        ],
    };
    std::fs::write(d.join("line.svg"), line.to_svg()).unwrap();
    let spp = [1.0, 2.0, 4.0, 8.0, 16.0, 32.0, 64.0, 128.0, 256.0];
    let err = LineChart {
        title: "relMSE vs spp".into(),
        x_label: "samples per pixel".into(),
        y_label: "relMSE".into(),
        x_log: true,
        y_log: true,
        series: vec![
            s("cpu", spp.iter().map(|&n| (n, 0.5 / n)).collect()),
            s("gpu", spp.iter().map(|&n| (n, if n == 8.0 { 0.0 } else { 0.6 / n })).collect()),
        ],
    };
    std::fs::write(d.join("loglog.svg"), err.to_svg()).unwrap();
    let small = LineChart {
        title: "small log".into(),
        x_label: "x".into(),
        y_label: "y".into(),
        x_log: false,
        y_log: true,
        series: vec![s("", vec![(0.0, 1.5), (1.0, 3.0), (2.0, 20.0), (3.0, 80.0)])],
    };
    std::fs::write(d.join("smalllog.svg"), small.to_svg()).unwrap();
    let one = LineChart {
        title: "single".into(),
        x_label: "x".into(),
        y_label: "y".into(),
        x_log: false,
        y_log: false,
        series: vec![s("only", vec![(3.0, 0.30000000000000004)])],
    };
    std::fs::write(d.join("single.svg"), one.to_svg()).unwrap();
    let passes = ["generate", "extend", "shade", "shadow", "compact", "accumulate"];
    let bars: Vec<Bar> = (0..8)
        .map(|i| Bar {
            label: format!("pool {}k", 64 << i),
            segments: passes
                .iter()
                .enumerate()
                .map(|(k, p)| (p.to_string(), 1.0 + (k as f64) * 0.7 + i as f64 * 0.3))
                .collect(),
        })
        .collect();
    std::fs::write(
        d.join("stacked.svg"),
        StackedBarChart { title: "Per-pass time".into(), y_label: "ms".into(), bars }.to_svg(),
    )
    .unwrap();
    let many: Vec<Bar> = (0..60)
        .map(|i| Bar {
            label: format!("config-{i} workgroup=64 compaction=prefix-sum"),
            segments: vec![("a".into(), 1.0 + (i % 7) as f64), ("b".into(), 2.0)],
        })
        .collect();
    std::fs::write(
        d.join("many.svg"),
        StackedBarChart { title: "Sixty bars".into(), y_label: "ms".into(), bars: many }.to_svg(),
    )
    .unwrap();
    let mid: Vec<Bar> = (0..20)
        .map(|i| Bar {
            label: format!("scene-{i}-variant"),
            segments: vec![("a".into(), 1.0 + (i % 7) as f64)],
        })
        .collect();
    std::fs::write(
        d.join("mid.svg"),
        StackedBarChart { title: "Twenty bars".into(), y_label: "ms".into(), bars: mid }.to_svg(),
    )
    .unwrap();
    let g = GroupedBarChart {
        title: "SIMD efficiency".into(),
        y_label: "active lanes".into(),
        y_max: Some(1.0),
        percent: true,
        groups: ["generate", "intersect", "shade", "compact"]
            .iter()
            .enumerate()
            .map(|(i, n)| {
                (
                    n.to_string(),
                    vec![
                        ("megakernel".into(), 0.2 + 0.1 * i as f64),
                        ("wavefront".into(), 0.93 - 0.05 * i as f64),
                        ("wavefront+sort".into(), 0.97),
                    ],
                )
            })
            .collect(),
    };
    std::fs::write(d.join("grouped.svg"), g.to_svg()).unwrap();
    let neg = GroupedBarChart {
        title: "Change vs baseline".into(),
        y_label: "Δ time (ms)".into(),
        y_max: None,
        percent: false,
        groups: vec![
            ("a".into(), vec![("x".into(), -2.0), ("y".into(), 1.5)]),
            ("b".into(), vec![("x".into(), 3.0), ("y".into(), f64::NAN)]),
        ],
    };
    std::fs::write(d.join("neg.svg"), neg.to_svg()).unwrap();
    std::fs::write(
        d.join("empty.svg"),
        LineChart { title: "Nothing here".into(), ..Default::default() }.to_svg(),
    )
    .unwrap();
    let mut grad = String::from("<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"512\" height=\"40\">");
    for i in 0..256 {
        grad += &format!(
            "<rect x=\"{}\" width=\"2\" height=\"40\" fill=\"{}\"/>",
            i * 2,
            hex(viridis(i as f32 / 255.0))
        );
    }
    grad += "</svg>";
    std::fs::write(d.join("viridis.svg"), grad).unwrap();
}
