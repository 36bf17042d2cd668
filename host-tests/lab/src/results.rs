//! `docs/results.md`: the hover report ([`crate::tables`]) and the flight report
//! ([`crate::flight_report`]) in one document. Above both, so that neither depends on the other.

use std::path::Path;

use rotorid_sim::plant::{trim_hover, Airframe};

use crate::error::ReportError;
use crate::flight_report::{
    conditions_markdown, flight_by_state, flight_markdown, noisy_markdown, Condition,
};
use crate::tables::{better_states, extended_markdown, list, table4_markdown, variants_markdown};
use rotorid_cli::report::Metrics;

/// The runs of the second plant: its hover pair's metrics and its envelope pair's (with the
/// directory of the latter, which holds params-flight.json).
pub struct SecondPlant<'a> {
    /// Which airframe was flown.
    pub airframe: Airframe,
    /// metrics.json of the hover identification/verification pair.
    pub hover: &'a Metrics,
    /// metrics.json of the envelope pair.
    pub envelope: &'a Metrics,
    /// Directory of the envelope run.
    pub envelope_dir: &'a Path,
}

/// The airframes side by side: the parameters that differ and what follows from them (trim
/// collective, flapping time constant, stick scaling), all from `rotorid_sim`.
fn airframes_markdown(airframes: &[Airframe]) -> Result<String, ReportError> {
    let mut rows: Vec<(String, Vec<String>)> = Vec::new();
    let mut push = |name: &str, cells: Vec<String>| rows.push((name.to_string(), cells));
    let params: Vec<_> = airframes.iter().map(|a| a.params()).collect();
    let col = |f: &dyn Fn(&rotorid_sim::plant::Helicopter) -> String| -> Vec<String> {
        params.iter().map(f).collect()
    };
    push("mass (kg)", col(&|p| format!("{:.2}", p.mass)));
    push(
        "inertia I_xx, I_yy, I_zz (kg·m²)",
        col(&|p| format!("{:.3}, {:.3}, {:.3}", p.ixx, p.iyy, p.izz)),
    );
    push(
        "rotor radius R (m)",
        col(&|p| format!("{:.3}", p.main.radius)),
    );
    push("head speed Ω (rad/s)", col(&|p| format!("{:.1}", p.omega)));
    push(
        "flapping Lock number γ (bar or blades)",
        col(&|p| format!("{:.2}", p.gamma_fb)),
    );
    push(
        "flapping time constant τ_e (s)",
        col(&|p| format!("{:.3}", p.tau_e())),
    );
    push(
        "cyclic-to-flapping gain A_lon = B_lat",
        col(&|p| format!("{:.1}", p.a_lon)),
    );
    push(
        "cyclic throw at full stick (rad)",
        col(&|p| format!("{:.3}", p.sticks.lon_gain)),
    );
    push(
        "hub stiffness K_β (N·m/rad)",
        col(&|p| format!("{:.1}", p.k_beta)),
    );
    push("speed flapping K_μ", col(&|p| format!("{:.1}", p.k_mu)));
    push(
        "tail rotor radius (m)",
        col(&|p| format!("{:.3}", p.tail.radius)),
    );
    push("fuselage S_x (m²)", col(&|p| format!("{:.3}", p.fus_sx)));
    let mut trims = Vec::new();
    let mut scales = Vec::new();
    for (a, p) in airframes.iter().zip(&params) {
        let plant = |source| ReportError::Plant {
            airframe: a.name(),
            source,
        };
        let t = trim_hover(p, 0.0).map_err(plant)?;
        trims.push(format!("{:.3}, {:.3}", t.sticks.col, t.sticks.ped));
        let k = a.stick_scale().map_err(plant)?;
        scales.push(format!(
            "{:.2}, {:.2}, {:.2}, {:.2}",
            k.col, k.ped, k.lon, k.lat
        ));
    }
    push("hover trim u_col, u_ped", trims);
    push("stick scale col, ped, lon, lat", scales);
    let mut s = format!(
        "| | {} |\n|---|{}\n",
        airframes
            .iter()
            .map(|a| a.title())
            .collect::<Vec<_>>()
            .join(" | "),
        "---:|".repeat(airframes.len())
    );
    for (name, cells) in rows {
        s += &format!("| {name} | {} |\n", cells.join(" | "));
    }
    Ok(s)
}

/// The section on the second plant: the airframes side by side, then the flight default's
/// state-by-state verdict and the same evidence as the X-Cell's ([`flight_markdown`]).
pub fn second_plant_markdown(second: &SecondPlant<'_>) -> Result<String, ReportError> {
    let mut template = include_str!("report_second_plant.md").to_string();
    let subs = [
        ("{{TITLE}}", second.airframe.title().to_string()),
        ("{{NAME}}", second.airframe.name().to_string()),
        (
            "{{AIRFRAMES}}",
            airframes_markdown(&[Airframe::XCell60, second.airframe])?,
        ),
        (
            "{{BY_STATE}}",
            flight_by_state(second.hover, second.envelope),
        ),
        (
            "{{FLIGHT}}",
            flight_markdown(
                second.hover,
                second.envelope,
                second.envelope_dir,
                second.airframe,
            )?,
        ),
    ];
    for (k, v) in subs {
        template = template.replace(k, &v);
    }
    Ok(template)
}

/// docs/results.md from the realistic and the clean run (and, if given, the envelope run and
/// the second plant's runs). Every number comes from the metrics.
pub fn results_markdown(
    realistic: &Metrics,
    clean: &Metrics,
    envelope: Option<(&Metrics, &Path)>,
    second: Option<&SecondPlant<'_>>,
    noisy: Option<&Metrics>,
    conditions: &[Condition],
    elapsed_s: Option<f64>,
) -> Result<String, ReportError> {
    let flight = match envelope {
        Some((m, dir)) => flight_markdown(realistic, m, dir, Airframe::XCell60)?,
        None => "(not run: `rotorid report` was given no `--envelope` metrics)\n".to_string(),
    };
    let second_plant = match second {
        Some(p) => second_plant_markdown(p)?,
        None => "(not run: `rotorid report` was given no second plant's metrics)\n".to_string(),
    };
    let t = realistic
        .table4
        .as_ref()
        .ok_or(ReportError::MissingTable4 { run: "realistic" })?;
    let tc = clean
        .table4
        .as_ref()
        .ok_or(ReportError::MissingTable4 { run: "clean" })?;
    let (better, worse) = better_states(t);
    let (better_c, worse_c) = better_states(tc);
    let missing = |role| ReportError::MissingVariant {
        run: "realistic",
        role,
    };
    let fz = realistic.variants.first().ok_or_else(|| missing("fuzzy"))?;
    let pl = realistic.variants.get(1).ok_or_else(|| missing("plain"))?;
    let mut template = include_str!("report_results.md").to_string();
    let subs: Vec<(&str, String)> = vec![
        ("{{FLIGHT}}", flight),
        ("{{SECOND_PLANT}}", second_plant),
        (
            "{{NOISY}}",
            noisy.map_or_else(
                || "(not run: `rotorid report` was given no `--noisy-hover` metrics)\n".to_string(),
                noisy_markdown,
            ),
        ),
        (
            "{{CONDITIONS}}",
            if conditions.is_empty() {
                "(not run: `rotorid report` was given no `--condition` runs)\n".to_string()
            } else {
                conditions_markdown(conditions)
            },
        ),
        ("{{TABLE4}}", table4_markdown(t)),
        ("{{TABLE4_CLEAN}}", table4_markdown(tc)),
        ("{{VARIANTS}}", variants_markdown(realistic)),
        ("{{EXTENDED}}", extended_markdown(realistic)),
        ("{{EXTENDED_CLEAN}}", extended_markdown(clean)),
        ("{{VARIANTS_CLEAN}}", variants_markdown(clean)),
        ("{{BETTER}}", list(&better)),
        ("{{WORSE}}", list(&worse)),
        ("{{BETTER_CLEAN}}", list(&better_c)),
        ("{{WORSE_CLEAN}}", list(&worse_c)),
        ("{{TRAIN_SAMPLES}}", realistic.training_samples.to_string()),
        (
            "{{VERIFY_SAMPLES}}",
            realistic.verification_samples.to_string(),
        ),
        ("{{TRAIN_FILES}}", realistic.training_files.join(", ")),
        ("{{VERIFY_FILE}}", realistic.verification_file.clone()),
        ("{{WINDOW}}", realistic.window_s.to_string()),
        ("{{WINDOWS}}", fz.free_run_windows.to_string()),
        ("{{DIVERGED_FUZZY}}", fz.free_run_diverged.to_string()),
        ("{{DIVERGED_PLAIN}}", pl.free_run_diverged.to_string()),
        (
            "{{DIVERGED_FUZZY_CLEAN}}",
            clean
                .variants
                .first()
                .map_or(0, |v| v.free_run_diverged)
                .to_string(),
        ),
        (
            "{{DIVERGED_PLAIN_CLEAN}}",
            clean
                .variants
                .get(1)
                .map_or(0, |v| v.free_run_diverged)
                .to_string(),
        ),
        (
            "{{ELAPSED}}",
            elapsed_s.map_or("(not measured)".to_string(), |e| format!("{e:.0} s")),
        ),
    ];
    for (k, v) in subs {
        template = template.replace(k, &v);
    }
    Ok(template)
}
