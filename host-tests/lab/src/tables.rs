//! The markdown tables of a run's metrics in docs/results.md: variants side by side, the
//! Table 4 analogue, the extended structures.

use rotorid_cli::report::{state_labels, Metrics, Table4};

fn row(label: &str, cells: &[String]) -> String {
    format!("| {label} | {} |\n", cells.join(" | "))
}

fn fmt4(x: &[f64; 6]) -> Vec<String> {
    x.iter().map(|v| format!("{v:.4}")).collect()
}

/// The per-variant tables in markdown: hold baseline, one-step (frozen and adapting), free
/// run and its hold baseline, one column per state.
pub fn variants_markdown(m: &Metrics) -> String {
    let mut s = String::new();
    s += &format!("| variant, error | {} |\n", state_labels().join(" | "));
    s += &format!("|---|{}\n", "---:|".repeat(6));
    if let Some(v) = m.variants.first() {
        s += &row("hold `x(k+1) = x(k)`, one step", &fmt4(&v.hold_one_step));
        s += &row(
            &format!("hold window start, {} s", m.window_s),
            &fmt4(&v.hold_free_run),
        );
    }
    for v in &m.variants {
        s += &row(
            &format!("{}, one step (θ frozen)", v.name),
            &fmt4(&v.one_step),
        );
        s += &row(
            &format!("{}, one step through its observer (θ frozen)", v.name),
            &fmt4(&v.one_step_observed),
        );
        s += &row(
            &format!("{}, one step (θ adapting)", v.name),
            &fmt4(&v.one_step_adapting),
        );
        s += &row(
            &format!("{}, one step on its training data", v.name),
            &fmt4(&v.training.one_step),
        );
        let rho: Vec<String> = v
            .training
            .convergence_ratio
            .iter()
            .zip(v.training.converged)
            .map(|(r, c)| format!("{r:.3}{}", if c { " (settled)" } else { "" }))
            .collect();
        s += &row(
            &format!("{}, convergence ρ = Σe²/ΣΔy² at end of training", v.name),
            &rho,
        );
        s += &row(
            &format!("{}, free run {} s", v.name, m.window_s),
            &fmt4(&v.free_run),
        );
    }
    s
}

/// Table 4 analogue beside the paper's, in markdown.
pub fn table4_markdown(t: &Table4) -> String {
    let mut s = String::new();
    s += "| state | fuzzy RLS | plain RLS | improvement | paper: fuzzy | paper: plain | paper: improvement |\n";
    s += "|---|---:|---:|---:|---:|---:|---:|\n";
    for (i, label) in state_labels().iter().enumerate() {
        s += &format!(
            "| {} | {:.4} | {:.4} | {:+.1} % | {:.4} | {:.4} | {:.1} % |\n",
            label,
            t.fuzzy[i],
            t.plain[i],
            t.improvement[i],
            t.paper_fuzzy[i],
            t.paper_plain[i],
            t.paper_improvement[i]
        );
    }
    s
}

/// States (by label) where the fuzzy one-step error is below the plain one.
pub(crate) fn better_states(t: &Table4) -> (Vec<String>, Vec<String>) {
    let mut better = Vec::new();
    let mut worse = Vec::new();
    for (i, label) in state_labels().into_iter().enumerate() {
        if t.fuzzy[i] < t.plain[i] {
            better.push(label);
        } else {
            worse.push(label);
        }
    }
    (better, worse)
}

pub(crate) fn list(v: &[String]) -> String {
    if v.is_empty() {
        "none".to_string()
    } else {
        v.join(", ")
    }
}

/// The issue-5 targets, checked on the metrics: the extended structure's free-run error on
/// q, r, p against the paper's (same rule layout: fuzzy with fuzzy, plain with plain), its
/// one-step error against hold on every state, and f32 against f64.
pub fn extended_markdown(m: &Metrics) -> String {
    let find = |name: &str| m.variants.iter().find(|v| v.name == name);
    let mark = |ok: bool| if ok { "✅" } else { "❌" };
    let mut s = String::new();
    s += "Free run over the verification flight, extended against the paper's structure (ratio below 0.5 = at least halved):

";
    s += "| pair | q ratio | r ratio | p ratio |
|---|---:|---:|---:|
";
    for (ext, paper) in [
        ("extended fuzzy", "paper fuzzy"),
        ("extended plain", "paper plain"),
    ] {
        if let (Some(e), Some(p)) = (find(ext), find(paper)) {
            let cells: Vec<String> = (3..6)
                .map(|i| {
                    let r = e.free_run[i] / p.free_run[i];
                    format!("{r:.2} {}", mark(r <= 0.5))
                })
                .collect();
            s += &row(&format!("{ext} / {paper}"), &cells);
        }
    }
    s += "
One-step error (θ frozen) against the hold baseline on every state (ratio below 1 = beats hold):

";
    s += &format!(
        "| variant | {} |
|---|{}
",
        state_labels().join(" | "),
        "---:|".repeat(6)
    );
    for name in [
        "extended fuzzy",
        "extended plain",
        "paper fuzzy",
        "paper plain",
    ] {
        if let Some(v) = find(name) {
            let cells: Vec<String> = (0..6)
                .map(|i| {
                    let r = v.one_step[i] / v.hold_one_step[i];
                    format!("{r:.3} {}", mark(r < 1.0))
                })
                .collect();
            s += &row(name, &cells);
        }
    }
    if !m.precision.is_empty() {
        s += &format!(
            "
f32 against f64 after the identification flight (flight settings: U-D RLS, helicopter scaling), over the well-excited parameters (posterior variance below {:.0e} of the prior, magnitude above {:.0e} of the model's largest):

",
            rotorid_cli::precision::WELL_EXCITED,
            rotorid_cli::precision::NEGLIGIBLE
        );
        s += "| variant | parameters | compared | max relative difference | median | target 1e-3 |
|---|---:|---:|---:|---:|---|
";
        for p in &m.precision {
            s += &format!(
                "| {} | {} | {} | {:.2e} | {:.2e} | {} |
",
                p.variant,
                p.parameters,
                p.compared,
                p.max_relative,
                p.median_relative,
                mark(p.max_relative <= 1e-3)
            );
        }
    }
    s
}
