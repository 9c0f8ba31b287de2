//! `cargo xtask bench-report --plot-only` (`papier-lab bench-report --plot-only`): draws the
//! frontier plots again from the numbers of the last report (`docs/benchmarks/sim_frontier.csv`)
//! without measuring anything, for a change to the plots alone. The CSV holds every row the
//! plots use: per configuration and scenario its median frame, c_mean and triangles (the
//! scaling rows and the fine mesh included). Rows of configurations the report no longer has
//! ([`retired`]: the XPBD solver, strip cutting) are left out, so a CSV written before they were
//! removed still plots.

use std::path::Path;

use anyhow::{Context, bail};
use sim_core::geometry::GeometryConfig;
use sim_core::physics::SolverConfig;
use sim_core::sheet::MeshConfig;

use super::{ScenarioResult, Variant, VariantResult};

/// The report's configuration groups (the CSV's `group` column).
const GROUPS: [&str; 8] = [
    "default",
    "physics",
    "newton",
    "density",
    "stiffness",
    "geometry",
    "scaling",
    "fine",
];

/// True for a row of a configuration removed from sim-core since: the XPBD solver's rows (its
/// own group and its density rows) and the strip-cutting row.
fn retired(label: &str, group: &str) -> bool {
    group == "xpbd" || label.starts_with("XPBD") || label.contains("(strip cutting on)")
}

/// Splits one CSV line: a quoted first field (the configuration, which may hold commas but no
/// quotes), then plain fields.
fn fields(line: &str) -> Option<(String, Vec<&str>)> {
    let rest = line.strip_prefix('"')?;
    let end = rest.find('"')?;
    let label = rest[..end].to_string();
    let tail = rest[end + 1..].strip_prefix(',')?;
    Some((label, tail.split(',').collect()))
}

/// The configurations of a frontier CSV, in file order: (frontier rows, scaling rows, fine mesh).
pub fn results_from_csv(
    text: &str,
) -> anyhow::Result<(Vec<VariantResult>, Vec<VariantResult>, VariantResult)> {
    let mut all: Vec<VariantResult> = Vec::new();
    for (i, line) in text.lines().enumerate().skip(1) {
        if line.trim().is_empty() {
            continue;
        }
        let (label, f) = fields(line).with_context(|| format!("CSV line {}", i + 1))?;
        if f.len() != 14 {
            bail!(
                "CSV line {}: {} fields after the label, want 14",
                i + 1,
                f.len()
            );
        }
        if retired(&label, f[0]) {
            continue;
        }
        let group = GROUPS
            .into_iter()
            .find(|g| *g == f[0])
            .with_context(|| format!("CSV line {}: unknown group {:?}", i + 1, f[0]))?;
        let num = |k: usize| -> anyhow::Result<f64> {
            f[k].parse()
                .with_context(|| format!("CSV line {}: field {:?}", i + 1, f[k]))
        };
        let int = |k: usize| -> anyhow::Result<u64> {
            f[k].parse()
                .with_context(|| format!("CSV line {}: field {:?}", i + 1, f[k]))
        };
        let scenario = ScenarioResult {
            name: f[2].to_string(),
            tris: num(3)?,
            frames: int(4)?,
            awake: int(5)?,
            median_ms: num(6)?,
            p99_ms: num(7)?,
            c_mean: num(8)?,
            n_comp: num(9)?,
            strain: num(10)?,
            iters: num(11)?,
            faults: int(12)?,
            singular: int(13)? as u32,
            geometry_median_ms: 0.0,
            geometry_p99_ms: 0.0,
            self_contact_mean_ms: 0.0,
        };
        match all.last_mut() {
            Some(v) if v.variant.label == label && v.variant.group == group => {
                v.scenarios.push(scenario);
            }
            _ => {
                all.push(VariantResult {
                    variant: Variant {
                        label,
                        group,
                        solver: SolverConfig::default(),
                        mesh: MeshConfig::default(),
                        geometry: GeometryConfig {
                            enabled: f[1] == "true",
                            ..GeometryConfig::default()
                        },
                    },
                    scenarios: vec![scenario],
                });
            }
        }
    }
    let fine = all
        .iter()
        .position(|v| v.variant.group == "fine")
        .map(|k| all.remove(k))
        .context("the CSV has no fine-mesh rows")?;
    let (scaling, results): (Vec<_>, Vec<_>) =
        all.into_iter().partition(|v| v.variant.group == "scaling");
    if results.is_empty() || scaling.len() < 2 {
        bail!("the CSV has no frontier or too few scaling rows");
    }
    Ok((results, scaling, fine))
}

/// Draws both frontier plots from `csv` into `png` and `png_scenes`.
pub fn replot(csv: &Path, png: &Path, png_scenes: &Path) -> anyhow::Result<()> {
    let text =
        std::fs::read_to_string(csv).with_context(|| format!("reading {}", csv.display()))?;
    let (results, scaling, fine) = results_from_csv(&text)?;
    let pts: Vec<(f64, f64)> = scaling
        .iter()
        .map(|r| (r.mean(|s| s.tris), r.median_ms()))
        .collect();
    let exponent = super::log_slope(&pts);
    super::plot(png, &results, &pts, exponent, &fine)?;
    super::plot_scenarios(png_scenes, &results, &fine)?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_report_csv_reads_back_into_its_configurations() {
        let csv = "configuration,group,geometry_layer,scenario,triangles,frames,awake_frames,median_ms,p99_ms,c_mean_pct,n_comp_pct,max_strain,newton_iters_per_substep,faults,singular\n\
            \"Newton 1×10 · L/9 + geometry (isometry every frame, 200 it.)\",geometry,true,c1,190,500,484,0.5,2.0,0.01,0.0,0.03,2.7,0,1\n\
            \"Newton 1×10 · L/9 + geometry (isometry every frame, 200 it.)\",geometry,true,s1,130,660,533,0.3,1.0,0.002,0.0,0.003,2.4,0,0\n\
            \"XPBD 5×1 · L/9\",xpbd,false,c1,190,500,484,0.4,1.0,0.7,17.0,0.1,0.0,3,0\n\
            \"XPBD 20×1 · L/6\",density,false,c1,66,500,484,0.2,1.0,0.9,20.0,0.1,0.0,0,0\n\
            \"Newton 1×10 · L/9 + geometry (strip cutting on)\",geometry,true,c1,190,500,484,0.5,2.0,0.01,0.0,0.03,2.7,0,1\n\
            \"Newton 1×1 · L/9\",newton,false,c1,190,500,484,0.2,1.0,0.05,1.0,0.05,1.0,0,0\n\
            \"Newton 1×10 · L/5\",scaling,false,c1,66,500,487,0.1,0.7,0.007,0.0,0.02,3.4,0,0\n\
            \"Newton 1×10 · L/9\",scaling,false,c1,190,500,485,0.32,2.3,0.009,0.0,0.03,2.7,0,0\n\
            \"Newton 1×10 · L/30\",fine,false,c1,1668,500,480,12.0,20.0,0.016,0.0,0.02,2.0,0,2\n";
        let (results, scaling, fine) = results_from_csv(csv).unwrap();
        assert_eq!(results.len(), 2);
        assert_eq!(results[0].scenarios.len(), 2);
        assert!(results[0].variant.geometry.enabled);
        assert_eq!(results[0].median_ms(), 0.4);
        // The retired rows (XPBD, strip cutting) are left out.
        assert_eq!(results[1].variant.label, "Newton 1×1 · L/9");
        assert!(!results[1].variant.geometry.enabled);
        assert_eq!(scaling.len(), 2);
        assert_eq!(fine.scenarios[0].tris, 1668.0);
    }

    #[test]
    fn a_damaged_csv_is_an_error() {
        assert!(
            results_from_csv("header\n\"a\",nogroup,false,c1,1,1,1,1,1,1,1,1,1,0,0\n").is_err()
        );
        assert!(results_from_csv("header\n\"a\",newton,false,c1,1\n").is_err());
        assert!(results_from_csv("header\nunquoted,newton\n").is_err());
        assert!(results_from_csv("header\n").is_err());
    }
}
