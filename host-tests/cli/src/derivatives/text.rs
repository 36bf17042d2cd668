//! The derivatives as console text (the verdict's block).

use super::{deg_s2, Derivative, Derivatives, RateAxis, Region};

/// `X_u −0.31±0.05*` (value and corrected SE, `*` when determined), `X_u —` when not fitted.
pub(super) fn short(d: Option<&Derivative>, sym: &str) -> String {
    match d.and_then(|d| d.value.zip(d.se).map(|v| (v, d.determined))) {
        Some(((v, se), det)) => format!("{sym} {v:+.3}±{se:.3}{}", if det { "*" } else { "" }),
        None => format!("{sym} —"),
    }
}

pub(super) fn rate_text(a: &RateAxis) -> String {
    let power = match (a.control_power_deg_s2_per_10pct, a.control_power_se_deg_s2) {
        (Some(p), Some(se)) => format!(
            "{:+.0}±{:.0}{}",
            p,
            0.1 * se,
            if a.control_determined { "*" } else { "" }
        ),
        _ => "—".to_string(),
    };
    let tau = match (a.time_constant_s, a.time_constant_se_s) {
        (Some(t), Some(se)) if t < 1.0 => format!("τ {t:.3}±{se:.3} s"),
        (Some(t), Some(se)) => format!("τ {t:.2}±{se:.2} s"),
        _ => format!("τ {}", a.time_constant_status),
    };
    let flag = if a.note.is_some() { " !" } else { "" };
    format!("{} {} {power}, {tau}{flag}", a.axis, a.control)
}

/// `    off-axis cyclic: M_lat +131±9* (21 % of M_lon), …`: the cross-coupling control
/// derivatives that the log determines (|value| ≥ 2 SE) where it determines the axis' own
/// control power too, in the control power's unit (deg/s² per 10 % stick) and as a share of
/// it. A rotor's flapping makes lateral cyclic pitch and longitudinal cyclic roll a
/// helicopter; the flight default's pitch and roll models have no such term
/// (docs/ab-off-axis.md), so a user sees where the log shows what the models cannot follow.
/// `None` when the log determines neither.
fn off_axis_text(r: &Region) -> Option<String> {
    let parts: Vec<String> = [("M_lat", "M_lon"), ("L_lon", "L_lat")]
        .iter()
        .filter_map(|&(cross, own)| {
            let d = r.derivative(cross).filter(|d| d.determined)?;
            let (v, se) = d.value.zip(d.se)?;
            // Only beside a determined control power of the axis' own: without it the stick
            // that drives the axis was hardly moved, and the off-axis one took its place.
            let o = r
                .derivative(own)
                .filter(|o| o.determined)
                .and_then(|o| o.value)
                .filter(|o| *o != 0.0)?;
            Some(format!(
                "{cross} {:+.0}±{:.0}* ({:.0} % of {own})",
                0.1 * deg_s2(v),
                0.1 * deg_s2(se),
                100.0 * (v / o).abs()
            ))
        })
        .collect();
    (!parts.is_empty()).then(|| {
        format!(
            "    off-axis cyclic: {}: the flight default's pitch and roll models have no off-axis term",
            parts.join(", ")
        )
    })
}

/// A compact console summary (at most 14 lines): per fitted region the control power per 10 %
/// of stick (deg/s²) and time constant of each rate axis, the off-axis control derivatives
/// the log determines, the translational derivatives, and the sticks that were never excited.
pub fn format_derivatives(d: &Derivatives) -> String {
    let mut lines = vec![
        "Body-axis derivatives (± corrected SE; * = determined, |value| ≥ 2 SE; control power in \
         deg/s² per 10 % stick; ! = see the axis' note):"
            .to_string(),
    ];
    let all_samples = d.regions.first().map(|r| r.samples);
    for (i, r) in d.regions.iter().enumerate() {
        if i > 0 && r.fitted && Some(r.samples) == all_samples {
            lines.push(format!(
                "  {} ({}): the same {} samples as {}",
                r.name,
                r.definition,
                r.samples,
                d.regions.first().map_or("", |a| a.name.as_str())
            ));
            continue;
        }
        if !r.fitted {
            lines.push(format!(
                "  {} ({}): not fitted: {}",
                r.name,
                r.definition,
                r.reason.as_deref().unwrap_or("")
            ));
            continue;
        }
        lines.push(format!(
            "  {} ({} samples): {}",
            r.name,
            r.samples,
            r.rate_axes
                .iter()
                .map(rate_text)
                .collect::<Vec<_>>()
                .join("; ")
        ));
        lines.extend(off_axis_text(r));
        let mut trans: Vec<String> = ["X_u", "Y_v", "Z_w", "Z_col"]
            .iter()
            .map(|s| short(r.derivative(s), s))
            .collect();
        trans[0].insert_str(0, "    ");
        let idle: Vec<&str> = r
            .excitation
            .iter()
            .filter(|e| e.never_excited)
            .map(|e| e.stick.as_str())
            .collect();
        let mut line = format!("{} (1/s, m/s² per stick)", trans.join(", "));
        if !idle.is_empty() {
            line.push_str(&format!("; never excited: {}", idle.join(", ")));
        }
        lines.push(line);
    }
    for n in d.notes.iter().take(2) {
        lines.push(format!("  note: {n}"));
    }
    if d.notes.len() > 2 {
        lines.push(format!(
            "  … {} more notes in metrics.json",
            d.notes.len() - 2
        ));
    }
    lines.join("\n")
}
