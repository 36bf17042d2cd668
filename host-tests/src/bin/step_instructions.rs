//! Runs `STEPS` identifier steps over the golden input stream, for counting instructions per
//! step with valgrind (`scripts/instructions.sh` runs it twice per identifier, with two step
//! counts, and reports the difference per step, so start-up and input generation cancel).
//!
//! Usage: `step_instructions <paper-fuzzy|paper-plain|extended-fuzzy|extended-plain> <ud|paper> <steps>`

use host_tests::golden;
use rotorid::hover::{HoverSample, StateModel};
use rotorid::{
    ExtendedFuzzyIdentifier, ExtendedPlainIdentifier, HoverConfig, HoverIdentifier,
    PaperFuzzyIdentifier, PaperPlainIdentifier,
};

fn run<V, Q, R, P>(
    mut id: HoverIdentifier<f32, V, Q, R, P>,
    inputs: &[HoverSample<f32>],
    steps: usize,
) -> u32
where
    V: StateModel<f32>,
    Q: StateModel<f32>,
    R: StateModel<f32>,
    P: StateModel<f32>,
{
    let mut acc = 0u32;
    for s in inputs.iter().take(steps) {
        if let Ok(out) = id.step(std::hint::black_box(s)) {
            acc ^= out.prediction.rates[0].to_bits();
        }
    }
    acc
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let (Some(kind), Some(form), Some(steps)) = (args.get(1), args.get(2), args.get(3)) else {
        eprintln!("usage: step_instructions <identifier> <ud|paper> <steps>");
        std::process::exit(2);
    };
    let Ok(steps) = steps.parse::<usize>() else {
        eprintln!("steps must be a number");
        std::process::exit(2);
    };
    let config = match form.as_str() {
        "ud" => HoverConfig::default(),
        "paper" => HoverConfig {
            rls: rotorid::rls::RlsConfig::paper(1e6),
            ..HoverConfig::default()
        },
        _ => {
            eprintln!("form must be ud or paper");
            std::process::exit(2);
        }
    };
    // Inputs for the largest run are generated whatever `steps` is, so that input generation
    // costs the same in both runs and cancels in the difference.
    let inputs = golden::inputs(5000, golden::SEED);
    let result = match kind.as_str() {
        "paper-fuzzy" => {
            PaperFuzzyIdentifier::paper_fuzzy(config).map(|id| run(id, &inputs, steps))
        }
        "paper-plain" => {
            PaperPlainIdentifier::paper_plain(config).map(|id| run(id, &inputs, steps))
        }
        "extended-fuzzy" => {
            ExtendedFuzzyIdentifier::extended_fuzzy(config).map(|id| run(id, &inputs, steps))
        }
        "extended-plain" => {
            ExtendedPlainIdentifier::extended_plain(config).map(|id| run(id, &inputs, steps))
        }
        _ => {
            eprintln!("unknown identifier {kind}");
            std::process::exit(2);
        }
    };
    match result {
        Ok(acc) => println!("{acc:08x}"),
        Err(e) => {
            eprintln!("{e}");
            std::process::exit(1);
        }
    }
}
