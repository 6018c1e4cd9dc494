//! `caustic converge` measures error against a reference over time: its table falls as the
//! samples grow (relMSE roughly as 1/spp for an unbiased render), and its plot and CSV are
//! written, for one integrator or several in turn.

use crate::support;
#[test]
fn error_falls_with_samples_and_outputs_are_written() {
    let dir = support::scratch("converge");
    let reference = dir.join("reference.exr");
    let rendered = support::caustic(&["render", "--size", "32x32", "--spp", "1024", "--seed", "99", "-o", reference.to_str().unwrap()]);
    // Independent numbers: the test is about the Monte Carlo rate (Sobol's is faster).
    assert!(rendered.status.success());
    let (csv, plot) = (dir.join("converge.csv"), dir.join("converge.svg"));
    let report = support::caustic_json(&[
        "converge",
        "--reference",
        reference.to_str().unwrap(),
        "--spp",
        "64",
        "--points-per-doubling",
        "1",
        "--sampler",
        "independent",
        "--csv",
        csv.to_str().unwrap(),
        "--plot",
        plot.to_str().unwrap(),
        "--json",
    ]);
    let points = report["points"].as_array().expect("points");
    let spp: Vec<u64> = points.iter().map(|p| p["spp"].as_u64().unwrap()).collect();
    assert_eq!(spp, [1, 2, 4, 8, 16, 32, 64]);
    let relmse: Vec<f64> = points.iter().map(|p| p["relmse"].as_f64().unwrap()).collect();
    let flip: Vec<f64> = points.iter().map(|p| p["flip"].as_f64().unwrap()).collect();
    println!("relMSE by spp: {relmse:?}\nFLIP-like by spp: {flip:?}");
    // Monte Carlo error falls as 1/spp: the least-squares slope of log relMSE against log spp
    // is about -1 (a little flatter at low spp, where the rare bright samples that dominate the
    // expectation are missing from a 1,024-pixel image, and near the 1024 spp reference's own
    // noise floor).
    let slope = log_log_slope(&spp.iter().map(|&n| n as f64).collect::<Vec<_>>(), &relmse);
    println!("log-log slope of relMSE against spp: {slope:.3} (expected about -1; accepted -1.25..-0.65)");
    assert!((-1.25..-0.65).contains(&slope));
    assert!(flip[6] < flip[0] * 0.5, "the perceptual error must fall too");
    // The estimate from the render alone (no reference), from the point before at half the
    // samples: absent at the first point, near the true relMSE after it.
    assert!(points[0]["estimated_relmse"].is_null());
    let estimated: Vec<f64> = points[1..].iter().map(|p| p["estimated_relmse"].as_f64().expect("an estimate")).collect();
    println!("estimated relMSE by spp from 2: {estimated:?}");
    let ratio = estimated[5] / relmse[6];
    println!("at 64 spp: estimated / true relMSE {ratio:.3} (independent samples, 1,024 pixels; accepted 0.5..2)");
    assert!((0.5..2.0).contains(&ratio));
    let table = std::fs::read_to_string(&csv).expect("csv");
    assert_eq!(table.lines().count(), 8, "header and 7 rows:\n{table}");
    assert!(std::fs::read_to_string(&plot).expect("svg").contains("<polyline"));
}

/// `--integrators`: each integrator measured in turn into one table (an integrator column),
/// one plot (a relMSE line each) and one report each; all of them unbiased here, so each
/// one's error falls; `--integrator` beside it and unknown names are usage errors.
#[test]
fn several_integrators_are_measured_into_one_table_and_plot() {
    let dir = support::scratch("converge-integrators");
    let reference = dir.join("reference.exr");
    assert!(support::caustic(&["render", "--size", "32x32", "--spp", "1024", "--seed", "99", "-o", reference.to_str().unwrap()]).status.success());
    let (csv, plot) = (dir.join("c.csv"), dir.join("c.svg"));
    let (reference, csv_arg, plot_arg) = (reference.to_str().unwrap(), csv.to_str().unwrap(), plot.to_str().unwrap());
    let report = support::caustic_json(&[
        "converge",
        "--reference",
        reference,
        "--spp",
        "16",
        "--points-per-doubling",
        "1",
        "--integrators",
        "pathtracer,bdpt,sppm",
        "--csv",
        csv_arg,
        "--plot",
        plot_arg,
        "--json",
    ]);
    let runs = report["runs"].as_array().expect("one report per integrator");
    let names: Vec<&str> = runs.iter().map(|r| r["integrator"].as_str().unwrap()).collect();
    assert_eq!(names, ["pathtracer", "bdpt", "sppm"]);
    for run in runs {
        let relmse: Vec<f64> = run["points"].as_array().unwrap().iter().map(|p| p["relmse"].as_f64().unwrap()).collect();
        println!("{}: relMSE by spp 1..16 {relmse:?}", run["integrator"]);
        assert_eq!(relmse.len(), 5);
        assert!(relmse[4] < 0.5 * relmse[0], "the error falls");
    }
    let table = std::fs::read_to_string(&csv).expect("csv");
    assert!(table.starts_with("integrator,spp,"), "{table}");
    assert_eq!(table.lines().filter(|l| l.starts_with("bdpt,")).count(), 5, "{table}");
    assert_eq!(table.lines().count(), 16, "header and 3 x 5 rows:\n{table}");
    let svg = std::fs::read_to_string(&plot).expect("svg");
    assert_eq!(svg.matches("<polyline").count(), 3);
    assert!(svg.contains("sppm relMSE"));
    for (extra, expected) in
        [(vec!["--integrator", "bdpt"], "cannot be used with"), (vec!["--integrators", "pathtracer,photons"], "unknown integrator 'photons'")]
    {
        let mut args = vec!["converge", "--reference", reference, "--spp", "2", "--csv", csv_arg];
        if extra[0] == "--integrator" {
            args.extend(["--integrators", "pathtracer"]);
        }
        args.extend(extra);
        let output = support::caustic(&args);
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert!(!output.status.success() && stderr.contains(expected), "{args:?}: {stderr}");
    }
}

/// Least-squares slope of ln y against ln x.
fn log_log_slope(x: &[f64], y: &[f64]) -> f64 {
    let (lx, ly): (Vec<f64>, Vec<f64>) = x.iter().zip(y).map(|(a, b)| (a.ln(), b.ln())).unzip();
    let n = lx.len() as f64;
    let (mx, my) = (lx.iter().sum::<f64>() / n, ly.iter().sum::<f64>() / n);
    let covariance: f64 = lx.iter().zip(&ly).map(|(a, b)| (a - mx) * (b - my)).sum();
    covariance / lx.iter().map(|a| (a - mx).powi(2)).sum::<f64>()
}

#[test]
fn a_reference_of_another_size_is_an_error() {
    let dir = support::scratch("converge-size");
    let reference = dir.join("reference.exr");
    assert!(support::caustic(&["render", "--size", "16x8", "--spp", "4", "-o", reference.to_str().unwrap()]).status.success());
    let output = support::caustic(&["converge", "--reference", reference.to_str().unwrap(), "--size", "32x32", "--csv", dir.join("c.csv").to_str().unwrap()]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(!output.status.success());
    assert!(stderr.contains("32x32") && stderr.contains("16x8"), "{stderr}");
    assert!(!dir.join("c.csv").exists(), "no table on failure");
}
