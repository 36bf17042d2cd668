//! The catalogue of identifier variants `rotorid identify` compares: the paper's, the extended
//! and the flight structures, their one-rule and locally learnt forms, and the flight default
//! with its terms selected from the training data ([`select_terms`](super::select_terms)).
//! These are the models a user may fly (the verdict's candidates) and the baselines the
//! verdict and the tables measure them against. The ablations that show what each of the
//! flight default's choices buys are the studies' (`rotorid-lab`), not the product's.

use rotorid::hover::flight_sets;
use rotorid::snapshot::KindCode;
use rotorid::{
    ExtendedFuzzyIdentifier, ExtendedLocalIdentifier, ExtendedPlainIdentifier, FlightIdentifier,
    FlightPlainIdentifier, HoverConfig, PaperFuzzyIdentifier, PaperLocalIdentifier,
    PaperPlainIdentifier,
};

use super::mask::SelectedFlight;
use super::selection::{select_terms, select_terms_and_schedules};
use super::variants::{at, Variant};

/// The identifier variants `rotorid identify` compares. The first two are Table 4's columns.
pub fn variants() -> Vec<Variant> {
    variants_with(true)
}

/// [`variants`], where without `premise_candidates` `flight selected` keeps every model's
/// rules on the flight default's speed and chooses its terms only ([`select_terms`];
/// `rotorid identify --no-premise-candidates`, the product before the premise candidates).
pub fn variants_with(premise_candidates: bool) -> Vec<Variant> {
    let mut all = catalogue();
    if !premise_candidates {
        for v in all.iter_mut().filter(|v| v.name == "flight selected") {
            v.build = |training, period| {
                let selection = select_terms(training, period)?;
                Ok(Box::new(SelectedFlight::new(selection.mask, period)?))
            };
        }
    }
    all
}

fn catalogue() -> Vec<Variant> {
    vec![
        Variant {
            name: "paper fuzzy",
            description:
                "Eqs. 27-30 with Table 3's sets (27+18+9+9 rules), U-D RLS, λ = 1, α = 1e6, unscaled",
            kind: Some(PaperFuzzyIdentifier::<f32>::KIND),
            build: |_, period| {
                Ok(Box::new(PaperFuzzyIdentifier::<f32>::paper_fuzzy(
                    at(HoverConfig::paper_robust(), period),
                )?))
            },
        },
        Variant {
            name: "paper plain",
            description: "Eqs. 19 and 26 (one rule per model), U-D RLS, λ = 1, α = 1e6, unscaled",
            kind: Some(PaperPlainIdentifier::<f32>::KIND),
            build: |_, period| {
                Ok(Box::new(PaperPlainIdentifier::<f32>::paper_plain(
                    at(HoverConfig::paper_robust(), period),
                )?))
            },
        },
        Variant {
            name: "extended fuzzy",
            description: "rates + damping, collective torque, trim (Table 3 sets, 18+9+9 rules); velocity + drag, tail-rotor side force (v_y sets, 3 rules); U-D RLS, helicopter scaling",
            kind: Some(ExtendedFuzzyIdentifier::<f32>::KIND),
            build: |_, period| {
                Ok(Box::new(ExtendedFuzzyIdentifier::<f32>::extended_fuzzy(
                    at(HoverConfig::default(), period),
                )?))
            },
        },
        Variant {
            name: "extended plain",
            description: "the extended terms with one rule per model; U-D RLS, helicopter scaling",
            kind: Some(ExtendedPlainIdentifier::<f32>::KIND),
            build: |_, period| {
                Ok(Box::new(ExtendedPlainIdentifier::<f32>::extended_plain(
                    at(HoverConfig::default(), period),
                )?))
            },
        },
        Variant {
            name: "paper local",
            description: "paper fuzzy's structure and Table 3 sets, each rule its own weighted RLS (local learning)",
            kind: Some(PaperLocalIdentifier::<f32>::KIND),
            build: |_, period| {
                Ok(Box::new(PaperLocalIdentifier::<f32>::paper_local(
                    at(HoverConfig::paper_robust(), period),
                )?))
            },
        },
        Variant {
            name: "extended local",
            description: "extended fuzzy's structure and sets, each rule its own weighted RLS (local learning)",
            kind: Some(ExtendedLocalIdentifier::<f32>::KIND),
            build: |_, period| {
                Ok(Box::new(ExtendedLocalIdentifier::<f32>::extended_local(
                    at(HoverConfig::default(), period),
                )?))
            },
        },
        Variant {
            name: "flight",
            description: "the flight default (FlightIdentifier): extended terms + speed and second-order rate terms, 3 rules per model on forward speed (0, 5, 10 m/s, σ 2.5), local learning, helicopter scaling",
            kind: Some(FlightIdentifier::<f32>::KIND),
            build: |_, period| {
                Ok(Box::new(FlightIdentifier::<f32>::flight(
                    at(HoverConfig::default(), period),
                    flight_sets(),
                )?))
            },
        },
        Variant {
            name: "flight plain",
            description: "the flight default's terms (incl. speed and second-order rate terms) with one rule per model: what the rules add",
            kind: Some(FlightPlainIdentifier::<f32>::KIND),
            build: |_, period| {
                Ok(Box::new(FlightPlainIdentifier::<f32>::flight_plain(
                    at(HoverConfig::default(), period),
                )?))
            },
        },
        Variant {
            name: "flight selected",
            description: "the flight default with the speed rules and optional terms its training data do not support switched off (per model: one rule instead of three if that is no worse, then backward elimination of terms, by free run on held-out blocks of the training data; a model's one rule is the first of three under sets that fire it alone, and a term is pinned at zero by a zero prior variance, so the exported state carries the choice), then per model that keeps three rules the speed they are on (forward, side or vertical) where the held-out blocks show it predicts better by more than their noise",
            kind: Some(FlightIdentifier::<f32>::KIND),
            build: |training, period| {
                let selection = select_terms_and_schedules(training, period)?;
                Ok(Box::new(SelectedFlight::new(selection.mask, period)?))
            },
        },
    ]
}
