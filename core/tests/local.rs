//! Local learning ([`rotorid::ts::local`]) and the flight identifier.
// Test code, outside `#[test]` functions: a panic here is a failed test (Cargo.toml's lints).
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::indexing_slicing)]
use rotorid::hover::{
    flight_sets, unscheduled_sets, Attitude, BodyFrame, Controls, HoverSample, HoverState,
    LocalRateModel, LocalVelocityModel, Premise, RateAxis, RateStructure, StateModel,
    VelocityStructure,
};
use rotorid::learning::Learning;
use rotorid::membership::MembershipFunction::{Gaussian, LeftShoulder, RightShoulder};
use rotorid::rls::{Algorithm, RlsConfig, RlsState};
use rotorid::rule_base::PremiseSets;
use rotorid::rule_base::RuleBase;
use rotorid::ts::local::LocalTsRls;
use rotorid::ts::local::MIN_LOCAL_STRENGTH;
use rotorid::ts::Scaling;
use rotorid::{
    Error, ExtendedPlainIdentifier, FlightIdentifier, FlightPlainIdentifier, HoverConfig,
    HoverIdentifier, Real,
};

/// A manoeuvring sample sequence: forward flight up to ~12 m/s and back, rates and sticks
/// moving, so that all three forward-speed rules fire.
fn sample<T: Real>(k: u64) -> HoverSample<T> {
    let t = k as f64 * 0.02;
    let speed = 6.0 - 6.0 * (0.05 * t).cos();
    let yaw = 0.3 * (0.07 * t).sin();
    let l = |x: f64| T::lit(x);
    HoverSample {
        time_us: 1_000_000 + k * 20_000,
        attitude: Attitude {
            roll: l(0.05 * (0.7 * t).sin()),
            pitch: l(-0.03 + 0.04 * (1.3 * t).cos()),
            yaw: l(yaw),
        },
        // Paper axes: x east, y up, z south; flying along the heading ψ.
        velocity: [
            l(speed * yaw.sin()),
            l(0.3 * (0.9 * t).cos()),
            l(-speed * yaw.cos()),
        ],
        rates: [
            l(5.0 * (2.0 * t).sin()),
            l(8.0 * (1.1 * t).cos()),
            l(-3.0 * (1.7 * t).sin()),
        ],
        controls: Controls {
            col: l(0.5 + 0.05 * (0.3 * t).sin()),
            ped: l(0.1 * (2.3 * t).sin()),
            lon: l(0.1 * (1.9 * t).cos()),
            lat: l(0.08 * (2.9 * t).sin()),
        },
    }
}

type LocalPlain = HoverIdentifier<
    f32,
    LocalVelocityModel<f32, 1, 7, 28>,
    LocalRateModel<f32, 1, 5, 15>,
    LocalRateModel<f32, 1, 5, 15>,
    LocalRateModel<f32, 1, 5, 15>,
>;

fn local_plain(config: HoverConfig<f32>) -> LocalPlain {
    let vs = VelocityStructure::Extended.helicopter_scaling();
    let one = || RuleBase::single_rule().unwrap();
    let rate = |axis| {
        LocalRateModel::with_scaling(
            axis,
            one(),
            RateStructure::Extended,
            Premise::Rates,
            config.rls,
            RateStructure::Extended.helicopter_scaling(axis),
        )
        .unwrap()
    };
    HoverIdentifier::new(
        LocalVelocityModel::with_scaling(
            one(),
            VelocityStructure::Extended,
            Premise::Velocity,
            config.rls,
            vs,
        )
        .unwrap(),
        rate(RateAxis::Pitch),
        rate(RateAxis::Yaw),
        rate(RateAxis::Roll),
        config,
    )
    .unwrap()
}

#[test]
fn one_rule_local_learning_is_global_learning_bit_for_bit() {
    let forgetting = RlsConfig::robust(1e6).with_forgetting(0.995, 1e9);
    let covariance = RlsConfig::paper(1e6);
    for rls in [RlsConfig::default(), forgetting, covariance] {
        let config = HoverConfig {
            rls,
            ..HoverConfig::default()
        };
        let mut global = ExtendedPlainIdentifier::<f32>::extended_plain(config).unwrap();
        let mut local = local_plain(config);
        assert_eq!(local.velocity_model().learning(), Learning::Local);
        assert_eq!(global.velocity_model().learning(), Learning::Global);
        for k in 0..600 {
            let s = sample::<f32>(k);
            let (a, b) = (global.step(&s).unwrap(), local.step(&s).unwrap());
            assert_eq!(
                a.prediction.to_array().map(f32::to_bits),
                b.prediction.to_array().map(f32::to_bits),
                "step {k}, {:?}",
                rls.algorithm
            );
            assert_eq!(
                a.innovation.map(|i| i.to_array().map(f32::to_bits)),
                b.innovation.map(|i| i.to_array().map(f32::to_bits))
            );
        }
        let (g, l) = (global.export(), local.export());
        assert_eq!(
            g.velocity.theta.map(f32::to_bits),
            l.velocity[0].theta.map(f32::to_bits)
        );
        assert_eq!(
            g.velocity.factor.map(f32::to_bits),
            l.velocity[0].factor.map(f32::to_bits)
        );
        assert_eq!(
            g.yaw.theta.map(f32::to_bits),
            l.yaw[0].theta.map(f32::to_bits)
        );
        assert_eq!(
            g.roll.factor.map(f32::to_bits),
            l.roll[0].factor.map(f32::to_bits)
        );
    }
}

fn flight() -> FlightIdentifier<f32> {
    FlightIdentifier::flight(HoverConfig::default(), flight_sets()).unwrap()
}

#[test]
fn flight_identifier_learns_every_rule_and_predicts_finite() {
    let mut id = flight();
    for k in 0..3000 {
        let out = id.step(&sample(k)).unwrap();
        assert!(out.prediction.to_array().iter().all(|x| x.is_finite()));
    }
    // The flight covers 0 to 12 m/s: every rule of every model has learnt.
    for rule in 0..3 {
        let r = id.yaw_model().ts().rule(rule).unwrap();
        assert!(
            r.counters().updates > 100,
            "rule {rule}: {:?}",
            r.counters()
        );
        assert!(r.parameters().iter().any(|&t| t != 0.0));
    }
    assert_eq!(id.pitch_model().premise(), Premise::HeadingVelocity);
    assert_eq!(id.pitch_model().structure(), RateStructure::Flight);
}

#[test]
fn flight_identifier_fits_3_kib_in_f32() {
    assert!(core::mem::size_of::<FlightIdentifier<f32>>() <= 3 * 1024);
}

#[test]
fn rejected_samples_change_nothing() {
    let mut id = flight();
    for k in 0..200 {
        id.step(&sample(k)).unwrap();
    }
    let before = id.clone();
    let mut bad = sample::<f32>(200);
    bad.rates[1] = f32::NAN;
    assert!(matches!(id.step(&bad), Err(Error::NonFinite(_))));
    let mut bad = sample::<f32>(200);
    bad.velocity[0] = 1e6;
    assert!(matches!(id.step(&bad), Err(Error::OutOfRange(_))));
    let mut late = sample::<f32>(200);
    late.time_us += 500_000;
    assert!(id.step(&late).is_err());
    assert!(id
        .predict_after(
            Some(&rotorid::HoverState {
                velocity: [0.0; 3],
                rates: [f32::INFINITY, 0.0, 0.0]
            }),
            &sample(200)
        )
        .is_err());
    assert_eq!(id, before);
    // And it goes on exactly as if nothing had been offered.
    let mut twin = before.clone();
    for k in 200..260 {
        let (a, b) = (id.step(&sample(k)).unwrap(), twin.step(&sample(k)).unwrap());
        assert_eq!(
            a.prediction.to_array().map(f32::to_bits),
            b.prediction.to_array().map(f32::to_bits)
        );
    }
}

#[test]
fn export_import_warm_start_continues_bit_for_bit() {
    let mut id = flight();
    for k in 0..400 {
        id.step(&sample(k)).unwrap();
    }
    let mut warm = flight();
    warm.import(&id.export()).unwrap();
    id.resume(&sample(400)).unwrap();
    warm.resume(&sample(400)).unwrap();
    for k in 401..500 {
        let (a, b) = (id.step(&sample(k)).unwrap(), warm.step(&sample(k)).unwrap());
        assert_eq!(
            a.prediction.to_array().map(f32::to_bits),
            b.prediction.to_array().map(f32::to_bits)
        );
    }
    // A corrupted state is refused whole.
    let mut state = id.export();
    state.roll[2].theta[0] = f32::NAN;
    let kept = warm.clone();
    assert!(warm.import(&state).is_err());
    assert_eq!(warm, kept);
}

/// Learns sample k−1 → k in one model through the model's own calls (`prepare_in`, `apply`),
/// as the identifier's step does, but never predicting: nothing is kept, so the firing
/// strengths and block products are computed afresh every time.
fn learn_afresh<M: StateModel<f32>>(model: &mut M, k: u64) -> HoverState<f32> {
    let (from, to) = (sample::<f32>(k - 1), sample::<f32>(k));
    let before = if k >= 2 {
        sample::<f32>(k - 2).state()
    } else {
        from.state()
    };
    let prepared = model
        .prepare_in(&from, &BodyFrame::of(&from.attitude), &before, &to)
        .unwrap();
    let mut innovation = HoverState::default();
    model.apply(&prepared, &mut innovation);
    innovation
}

fn bits(s: &HoverState<f32>) -> [u32; 6] {
    s.to_array().map(f32::to_bits)
}

#[test]
fn kept_strengths_give_the_bits_of_a_recomputation() {
    // The rate models on the forward speed, the velocity model on the horizontal speed: the
    // yaw and roll models take the pitch model's ξ.
    matches_models_learning_afresh(flight());
}

#[test]
fn rate_models_take_the_velocity_models_strengths_where_it_is_scheduled_as_they_are() {
    // A translational model on the forward speed with the rates' sets: the three rate models
    // take its ξ.
    let flight = flight();
    let config = HoverConfig::default();
    let rules = RuleBase::new([flight_sets(), PremiseSets::new(), PremiseSets::new()]).unwrap();
    let velocity = LocalVelocityModel::<f32, 3, 8, 36>::with_scaling(
        rules,
        VelocityStructure::Flight,
        Premise::HeadingVelocity,
        config.rls,
        VelocityStructure::Flight.helicopter_scaling(),
    )
    .unwrap();
    let id = HoverIdentifier::new(
        velocity,
        flight.pitch_model().clone(),
        flight.yaw_model().clone(),
        flight.roll_model().clone(),
        config,
    )
    .unwrap();
    matches_models_learning_afresh(id);
}

/// Under `unscheduled_sets` the flight structure is its one-rule form, bit for bit: the
/// first rule fires with ξ = 1 and learns as the plain model's only rule; the others stay at
/// their prior.
#[test]
fn unscheduled_models_are_the_plain_models_bit_for_bit() {
    let config = HoverConfig::default();
    let mut unscheduled = FlightIdentifier::<f32>::flight_per_model(
        config,
        core::array::from_fn(|_| unscheduled_sets()),
    )
    .unwrap();
    let mut plain = FlightPlainIdentifier::<f32>::flight_plain(config).unwrap();
    for k in 0..1500 {
        let s = sample(k);
        let (a, b) = (unscheduled.step(&s).unwrap(), plain.step(&s).unwrap());
        assert_eq!(bits(&a.prediction), bits(&b.prediction), "sample {k}");
        assert_eq!(
            a.innovation.map(|i| bits(&i)),
            b.innovation.map(|i| bits(&i))
        );
    }
    let (a, b) = (unscheduled.export(), plain.export());
    first_rule_is_the_only_one(&a.velocity, &b.velocity[0]);
    first_rule_is_the_only_one(&a.pitch, &b.pitch[0]);
    first_rule_is_the_only_one(&a.yaw, &b.yaw[0]);
    first_rule_is_the_only_one(&a.roll, &b.roll[0]);
}

/// `rules[0]` is `only`, bit for bit, and the other rules never learnt.
fn first_rule_is_the_only_one<const D: usize, const DP: usize>(
    rules: &[RlsState<f32, D, DP>],
    only: &RlsState<f32, D, DP>,
) {
    let bits = |r: &[f32]| r.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&rules[0].theta), bits(&only.theta));
    assert_eq!(bits(&rules[0].factor), bits(&only.factor));
    assert_eq!(rules[0].updates, only.updates);
    assert!(only.updates > 1000);
    assert!(rules[1..]
        .iter()
        .all(|r| r.updates == 0 && r.theta.iter().all(|&t| t == 0.0)));
}

/// One model unscheduled among scheduled ones: the others keep sharing their strengths, and
/// every model learns as it would alone.
#[test]
fn an_unscheduled_model_among_scheduled_ones_learns_as_it_would_alone() {
    let config = HoverConfig::default();
    let sets = [
        flight_sets(),
        flight_sets(),
        flight_sets(),
        unscheduled_sets(),
    ];
    let id = FlightIdentifier::<f32>::flight_per_model(config, sets).unwrap();
    assert!(id.roll_model().premise_sets().1[0] == unscheduled_sets::<f32>());
    matches_models_learning_afresh(id);
}

/// `flight_scheduled`: a model scheduled on the side or the vertical speed has its sets on
/// that premise variable and learns as it would alone (the models that keep the speed still
/// share their strengths); the speed four times is `flight_per_model`, bit for bit; the
/// translational model has no side speed to be scheduled on.
#[test]
fn models_scheduled_on_the_side_or_the_vertical_speed() {
    use rotorid::hover::Scheduling::{SideSpeed, Speed, VerticalSpeed};
    let config = HoverConfig::default();
    // The samples' vertical speed swings ±0.3 m/s; their side speed is 0 (they fly along
    // the heading).
    let small = || rotorid::hover::table3::three_sets((-0.2, 0.1), (0.0, 0.1), (0.2, 0.1));
    let sets = [small(), flight_sets(), small(), small()];
    let on = [VerticalSpeed, Speed, SideSpeed, VerticalSpeed];
    let id = FlightIdentifier::<f32>::flight_scheduled(config, sets.clone(), on).unwrap();
    let variables = |m: &dyn Fn(usize) -> bool| (0..3).map(m).collect::<Vec<_>>();
    let velocity = id.velocity_model().premise_sets().1;
    assert_eq!(
        variables(&|i| !velocity[i].is_empty()),
        [false, true, false]
    );
    let yaw = id.yaw_model().premise_sets().1;
    assert_eq!(variables(&|i| !yaw[i].is_empty()), [false, true, false]);
    let roll = id.roll_model().premise_sets().1;
    assert!(roll[2] == small() && roll[0].is_empty() && roll[1].is_empty());
    let mut learnt = id.clone();
    for k in 0..1500 {
        learnt.step(&sample(k)).unwrap();
    }
    // On the vertical speed every rule of the roll model learns, and it learns otherwise
    // than on the forward speed.
    let mut default = FlightIdentifier::<f32>::flight(config, flight_sets()).unwrap();
    for k in 0..1500 {
        default.step(&sample(k)).unwrap();
    }
    let (roll, default_roll) = (learnt.export().roll, default.export().roll);
    assert!(roll.iter().all(|r| r.updates > 100));
    assert!(roll != default_roll);
    matches_models_learning_afresh(id);

    let flight_sets4 = || core::array::from_fn(|_| flight_sets());
    let mut a =
        FlightIdentifier::<f32>::flight_scheduled(config, flight_sets4(), [Speed; 4]).unwrap();
    let mut b = FlightIdentifier::<f32>::flight_per_model(config, flight_sets4()).unwrap();
    for k in 0..500 {
        let s = sample(k);
        assert_eq!(
            bits(&a.step(&s).unwrap().prediction),
            bits(&b.step(&s).unwrap().prediction)
        );
    }
    assert!(a.export() == b.export());
    let side = [SideSpeed, Speed, Speed, Speed];
    assert_eq!(
        FlightIdentifier::<f32>::flight_scheduled(config, sets, side).unwrap_err(),
        Error::Config(rotorid::error::ConfigError::Dimensions)
    );
}

#[test]
fn shared_strengths_give_the_bits_of_a_recomputation_where_one_model_differs() {
    // The yaw model on forward and side speed (9 rules) cannot take the pitch model's ξ and
    // computes its own; the roll model after it still takes them.
    let flight = flight();
    let config = HoverConfig::default();
    let side = rotorid::hover::table3::three_sets((-5.0, 2.5), (0.0, 2.5), (5.0, 2.5));
    let rules = RuleBase::new([flight_sets(), side, PremiseSets::new()]).unwrap();
    let id = HoverIdentifier::new(
        flight.velocity_model().clone(),
        flight.pitch_model().clone(),
        flight_yaw::<9>(rules),
        flight.roll_model().clone(),
        config,
    )
    .unwrap();
    matches_models_learning_afresh(id);
}

#[test]
fn a_model_replaced_through_its_mut_access_is_not_given_the_old_sets_strengths() {
    // The identifier finds once which models share the velocity or the pitch model's sets; a
    // yaw model with other sets put in its place must compute its own again.
    let mut id = flight();
    for k in 0..5 {
        id.step(&sample(k)).unwrap();
    }
    let moved = rotorid::hover::table3::three_sets((0.0, 2.5), (6.0, 3.0), (10.0, 2.5));
    let rules = RuleBase::new([moved, PremiseSets::new(), PremiseSets::new()]).unwrap();
    *id.yaw_model_mut() = flight_yaw::<3>(rules);
    id.end_chain();
    matches_models_learning_afresh(id);
}

/// A yaw model with the flight identifier's terms and settings over other rules.
fn flight_yaw<const R: usize>(rules: RuleBase<f32, 3, R>) -> LocalRateModel<f32, R, 7, 28> {
    LocalRateModel::with_scaling(
        RateAxis::Yaw,
        rules,
        RateStructure::Flight,
        Premise::HeadingVelocity,
        HoverConfig::default().rls,
        RateStructure::Flight.helicopter_scaling(RateAxis::Yaw),
    )
    .unwrap()
}

/// `id` learns each sample with the ξ and block products kept from its prediction at the
/// step before (and the ξ one model shares with the others); copies of its four models
/// compute them afresh. θ, P, the innovations and the step's prediction must agree bit for
/// bit at every step, and so must a prediction from another sample (whose premise differs
/// from the one kept).
fn matches_models_learning_afresh<Vm, Qm, Rm, Pm>(mut id: HoverIdentifier<f32, Vm, Qm, Rm, Pm>)
where
    Vm: StateModel<f32, State: PartialEq + core::fmt::Debug> + Clone,
    Qm: StateModel<f32, State: PartialEq + core::fmt::Debug> + Clone,
    Rm: StateModel<f32, State: PartialEq + core::fmt::Debug> + Clone,
    Pm: StateModel<f32, State: PartialEq + core::fmt::Debug> + Clone,
{
    let (mut v, mut q) = (id.velocity_model().clone(), id.pitch_model().clone());
    let (mut r, mut p) = (id.yaw_model().clone(), id.roll_model().clone());
    id.step(&sample(0)).unwrap();
    for k in 1..1500 {
        let out = id.step(&sample(k)).unwrap();
        let mut innovation = learn_afresh(&mut v, k);
        innovation.rates[0] = learn_afresh(&mut q, k).rates[0];
        innovation.rates[1] = learn_afresh(&mut r, k).rates[1];
        innovation.rates[2] = learn_afresh(&mut p, k).rates[2];
        assert_eq!(out.innovation.map(|i| bits(&i)), Some(bits(&innovation)));
        let (now, before) = (sample::<f32>(k), sample::<f32>(k - 1).state());
        let frame = BodyFrame::of(&now.attitude);
        let mut expected = HoverState::default();
        for model in [&v as &dyn Predicts, &q, &r, &p] {
            model.predict_in_into(&now, &frame, &before, &mut expected);
        }
        assert_eq!(bits(&out.prediction), bits(&expected), "sample {k}");
        let elsewhere = sample::<f32>(k + 1000);
        let mut expected = HoverState::default();
        for model in [&v as &dyn Predicts, &q, &r, &p] {
            model.predict_into(&elsewhere, &mut expected);
        }
        let predicted = id.predict_after(None, &elsewhere).unwrap();
        assert_eq!(bits(&predicted), bits(&expected), "sample {k}");
        assert_eq!(id.velocity_model().export(), v.export(), "sample {k}");
        assert_eq!(id.pitch_model().export(), q.export(), "sample {k}");
        assert_eq!(id.yaw_model().export(), r.export(), "sample {k}");
        assert_eq!(id.roll_model().export(), p.export(), "sample {k}");
    }
}

#[test]
fn a_model_imported_mid_chain_does_not_reuse_what_it_kept() {
    // Importing one model does not restart the chain, and it changes θ: the next update must
    // not reuse block products computed with the old θ.
    let mut other = flight();
    for k in 0..700 {
        other.step(&sample(k + 3000)).unwrap();
    }
    let yaw = other.yaw_model().export();
    let mut id = flight();
    for k in 0..300 {
        id.step(&sample(k)).unwrap();
    }
    id.yaw_model_mut().import(&yaw).unwrap();
    // A model that never predicted, with the same θ and P.
    let mut afresh = flight().yaw_model().clone();
    afresh.import(&yaw).unwrap();
    for k in 300..400 {
        let out = id.step(&sample(k)).unwrap();
        let innovation = learn_afresh(&mut afresh, k);
        let r = out.innovation.map(|i| i.rates[1].to_bits());
        assert_eq!(r, Some(innovation.rates[1].to_bits()), "sample {k}");
        assert_eq!(id.yaw_model().export(), afresh.export(), "sample {k}");
    }
}

#[test]
fn learning_through_a_model_drops_what_it_kept() {
    let mut id = flight();
    for k in 0..300 {
        id.step(&sample(k)).unwrap();
    }
    // The yaw model keeps ξ and b of its prediction from sample 299; learning 299 → 300
    // changes θ, so a prediction from sample 299 afterwards must not reuse b.
    let mut model = id.yaw_model().clone();
    let mut afresh = flight().yaw_model().clone();
    afresh.import(&model.export()).unwrap();
    learn_afresh(&mut model, 300);
    learn_afresh(&mut afresh, 300);
    let (mut a, mut b) = (HoverState::default(), HoverState::default());
    model.predict(&sample(299), &mut a).unwrap();
    afresh.predict(&sample(299), &mut b).unwrap();
    assert_eq!(bits(&a), bits(&b));
}

/// A model's one-step prediction, object-safe (the four models differ in type).
trait Predicts {
    fn predict_into(&self, s: &HoverSample<f32>, next: &mut HoverState<f32>);
    fn predict_in_into(
        &self,
        s: &HoverSample<f32>,
        frame: &BodyFrame<f32>,
        before: &HoverState<f32>,
        next: &mut HoverState<f32>,
    );
}

impl<M: StateModel<f32>> Predicts for M {
    fn predict_into(&self, s: &HoverSample<f32>, next: &mut HoverState<f32>) {
        self.predict(s, next).unwrap();
    }
    fn predict_in_into(
        &self,
        s: &HoverSample<f32>,
        frame: &BodyFrame<f32>,
        before: &HoverState<f32>,
        next: &mut HoverState<f32>,
    ) {
        self.predict_in(s, frame, before, next).unwrap();
    }
}

#[test]
fn predict_after_reads_the_sample_before_for_the_second_order_term_and_the_drag() {
    let mut id = flight();
    for k in 0..500 {
        id.step(&sample(k)).unwrap();
    }
    let (s0, s1) = (sample::<f32>(500), sample::<f32>(501));
    // Without a sample before, the sample itself stands in: as if the state were steady.
    let steady = id.predict_after(Some(&s1.state()), &s1).unwrap().to_array();
    assert_eq!(steady, id.predict(&s1).unwrap().to_array());
    // The rates of the sample before move the rate predictions only (the second-order
    // term)...
    let rates_before = HoverState {
        velocity: s1.velocity,
        rates: s0.rates,
    };
    let moving = id
        .predict_after(Some(&rates_before), &s1)
        .unwrap()
        .to_array();
    assert_ne!(steady[3..], moving[3..]);
    assert_eq!(steady[..3], moving[..3]);
    // ...and its velocity the velocity prediction only (the horizontal drag on v(k−1)).
    let velocity_before = HoverState {
        velocity: s0.velocity,
        rates: s1.rates,
    };
    let drifting = id
        .predict_after(Some(&velocity_before), &s1)
        .unwrap()
        .to_array();
    assert_ne!(steady[..3], drifting[..3]);
    assert_eq!(steady[3..], drifting[3..]);
    // Of that velocity, only the horizontal components: the heave damping is on v_y(k) (the
    // identifier's chain does not keep v_y(k−1)).
    let mut climbing = s1.state();
    climbing.velocity[1] = s0.velocity[1] + 1.0;
    let same = id.predict_after(Some(&climbing), &s1).unwrap().to_array();
    assert_eq!(steady.map(f32::to_bits), same.map(f32::to_bits));
    // A state before that no sample could have is refused.
    let mut bad = s0.state();
    bad.velocity[2] = f32::INFINITY;
    assert!(id.predict_after(Some(&bad), &s1).is_err());
}

#[test]
fn a_rule_that_does_not_describe_the_data_learns_nothing() {
    let sets = rotorid::hover::table3::sets(&[
        LeftShoulder {
            centre: 0.0f64,
            spread: 0.5,
        },
        Gaussian {
            centre: 5.0,
            spread: 0.5,
        },
        RightShoulder {
            centre: 10.0,
            spread: 0.5,
        },
    ]);
    let rules = RuleBase::new([sets, Default::default()]).unwrap();
    let mut ts =
        LocalTsRls::<f64, 2, 3, 2, 3>::with_scaling(rules, RlsConfig::default(), Scaling::unit())
            .unwrap();
    // Premise at 0: rule 1's strength exp(-50) and rule 2's exp(-200) are far below the
    // threshold, so only rule 0 learns.
    assert!((-50.0f64).exp() < MIN_LOCAL_STRENGTH);
    for k in 0..50 {
        let x = k as f64 * 0.1;
        let p = ts
            .prepare(&[0.0, 0.0], &[[x, 1.0]], &[2.0 * x + 1.0])
            .unwrap();
        ts.apply(&p);
    }
    assert!((ts.physical_parameter(0, 0).unwrap() - 2.0).abs() < 1e-6);
    assert!((ts.physical_parameter(0, 1).unwrap() - 1.0).abs() < 1e-6);
    for rule in 1..3 {
        assert_eq!(ts.rule(rule).unwrap().counters().updates, 0);
        assert_eq!(ts.rule(rule).unwrap().parameters(), &[0.0, 0.0]);
    }
    assert_eq!(ts.config().algorithm, Algorithm::UdFactor);
    // Prediction is Σ ξ_i Δᵀθ_i: at the premise of rule 0 alone, rule 0's model.
    let [y] = ts.predict_many(&[0.0, 0.0], &[[3.0, 1.0]]).unwrap();
    assert!((y - 7.0).abs() < 1e-5);
}

#[test]
fn the_flight_identifier_runs_in_f64() {
    let mut id = FlightIdentifier::<f64>::flight(HoverConfig::default(), flight_sets()).unwrap();
    for k in 0..1000 {
        let out = id.step(&sample::<f64>(k)).unwrap();
        assert!(out.prediction.to_array().iter().all(|x| x.is_finite()));
    }
}

/// Each rule's θ_i is the fuzzily weighted least-squares fit of the data with weights ξ_i,
/// `θ_i = (Σ ξ_i Δ Δᵀ + P(0)⁻¹)⁻¹ Σ ξ_i Δ y`, solved here in batch (nalgebra, f64), for
/// both forms, on two rules that overlap and a few rows of weight under 1 %. A weight taken
/// as √ξ_i or 1/ξ_i instead would miss it by far more than the tolerance.
#[test]
fn each_rule_solves_its_weighted_least_squares_problem() {
    use nalgebra::{Matrix3, Vector3};
    let sets = rotorid::hover::table3::sets(&[
        LeftShoulder {
            centre: 0.0f64,
            spread: 2.0,
        },
        RightShoulder {
            centre: 4.0,
            spread: 2.0,
        },
    ]);
    let rules = RuleBase::<f64, 2, 2>::new([sets, Default::default()]).unwrap();
    for algorithm in [Algorithm::UdFactor, Algorithm::Covariance] {
        let alpha = 1e4;
        let config = RlsConfig {
            algorithm,
            ..RlsConfig::robust(alpha)
        };
        let mut ts =
            LocalTsRls::<f64, 2, 2, 3, 6>::with_scaling(rules.clone(), config, Scaling::unit())
                .unwrap();
        let mut normal = [Matrix3::<f64>::identity() / alpha; 2];
        let mut moment = [Vector3::<f64>::zeros(); 2];
        let mut seed = 0x1234_5678u32;
        let mut uniform = || {
            seed ^= seed << 13;
            seed ^= seed >> 17;
            seed ^= seed << 5;
            f64::from(seed >> 8) / f64::from(1u32 << 24)
        };
        let mut light = 0;
        for _ in 0..400 {
            let premise = [12.0 * uniform() - 4.0, 0.0];
            let terms = [uniform() - 0.5, 2.0 * uniform() - 1.0, 1.0];
            let y = 3.0 * terms[0] - terms[1] + 0.5 + 0.1 * (uniform() - 0.5);
            let xi = rules.firing_strengths(&premise).unwrap();
            let p = ts.prepare(&premise, &[terms], &[y]).unwrap();
            ts.apply(&p);
            let d = Vector3::from(terms);
            for (i, &w) in xi.iter().enumerate() {
                if w >= MIN_LOCAL_STRENGTH {
                    normal[i] += w * d * d.transpose();
                    moment[i] += w * y * d;
                    light += usize::from(w < 0.01);
                }
            }
        }
        assert!(light > 5, "too few rows of weight under 1 %: {light}");
        for (i, (n, m)) in normal.iter().zip(moment.iter()).enumerate() {
            let want = n.lu().solve(m).unwrap();
            for (s, &w) in want.iter().enumerate() {
                let got = ts.physical_parameter(i, s).unwrap();
                assert!(
                    (got - w).abs() <= 1e-9 * (1.0 + w.abs()),
                    "{algorithm:?} rule {i} term {s}: {got} vs {w}"
                );
            }
        }
    }
}
