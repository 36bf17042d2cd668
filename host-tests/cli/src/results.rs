//! `docs/results.md`: the hover report ([`crate::report`]) and the flight report
//! ([`crate::flight_report`]) in one document. Above both, so that neither depends on the other.

use crate::report::*;

/// docs/results.md from the realistic and the clean run. Every number comes from the metrics.
pub fn results_markdown(
    realistic: &Metrics,
    clean: &Metrics,
    envelope: Option<(&Metrics, &std::path::Path)>,
    elapsed_s: Option<f64>,
) -> Result<String, ReportError> {
    let flight = match envelope {
        Some((m, dir)) => crate::flight_report::flight_markdown(realistic, m, dir)?,
        None => "(not run: `rotorid report` was given no `--envelope` metrics)\n".to_string(),
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
