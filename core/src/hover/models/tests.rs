//! Unit tests of the models' shared parts.

use super::{Premise, SharedStrengths};
use crate::hover::flight_sets;
use crate::hover::table3::three_sets;
use crate::membership::MembershipFunction::LeftShoulder;
use crate::rule_base::{PremiseSets, RuleBase};

#[test]
fn shared_strengths_are_taken_only_by_the_same_premise_and_sets() {
    let none = PremiseSets::<f32>::new;
    let forward = RuleBase::<f32, 3, 3>::new([flight_sets(), none(), none()]).unwrap();
    let xi = forward.firing_strengths(&[4.0, 1.0, 0.0]).unwrap();
    let shared = SharedStrengths::new(Premise::HeadingVelocity, &forward, &xi);
    let twin = RuleBase::<f32, 3, 3>::new([flight_sets(), none(), none()]).unwrap();
    assert_eq!(shared.for_rules(Premise::HeadingVelocity, &twin), Some(&xi));
    // Another premise, other sets, the same sets on another variable, another rule count.
    assert_eq!(shared.for_rules(Premise::Velocity, &twin), None);
    let moved = three_sets((0.0, 2.5), (5.5, 2.5), (10.0, 2.5));
    let moved = RuleBase::<f32, 3, 3>::new([moved, none(), none()]).unwrap();
    assert_eq!(shared.for_rules(Premise::HeadingVelocity, &moved), None);
    let side = RuleBase::<f32, 3, 3>::new([none(), flight_sets(), none()]).unwrap();
    assert_eq!(shared.for_rules(Premise::HeadingVelocity, &side), None);
    let one = RuleBase::<f32, 3, 1>::single_rule().unwrap();
    assert_eq!(shared.for_rules(Premise::HeadingVelocity, &one), None);
    // Sets are compared bit for bit: a centre of −0 is another set (which would give the
    // same strengths, but sharing does not rely on that).
    let minus = three_sets((-0.0, 2.5), (5.0, 2.5), (10.0, 2.5));
    let minus = RuleBase::<f32, 3, 3>::new([minus, none(), none()]).unwrap();
    assert_eq!(shared.for_rules(Premise::HeadingVelocity, &minus), None);
    // A shoulder where the twin has a Gaussian, same centre and spread.
    let mut kinds = flight_sets::<f32>();
    kinds[1] = LeftShoulder {
        centre: 5.0,
        spread: 2.5,
    };
    let kinds = RuleBase::<f32, 3, 3>::new([kinds, none(), none()]).unwrap();
    assert_eq!(shared.for_rules(Premise::HeadingVelocity, &kinds), None);
}
