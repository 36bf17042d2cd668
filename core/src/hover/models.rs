//! The four state models of the hover identifier: thin wrappers that turn a [`HoverSample`]
//! into the premise and consequent terms of a [`TsRls`].

use crate::error::{ConfigError, Error};
use crate::hover::sample::{HoverSample, HoverState};
use crate::rls::{RlsConfig, RlsState};
use crate::rule_base::RuleBase;
use crate::scalar::Real;
use crate::ts::{Prepared, TsRls};

/// What a [`HoverIdentifier`](crate::hover::HoverIdentifier) needs of each of its models.
///
/// Learning is split in two so that the identifier can check all four models before it
/// changes any: [`prepare`](Self::prepare) checks and computes, [`apply`](Self::apply) writes.
pub trait StateModel<T: Real> {
    /// A checked update, ready to apply.
    type Prepared;
    /// What [`export`](Self::export) returns and [`import`](Self::import) takes.
    type State: Copy;

    /// Checks and computes the update from sample k (`from`) to sample k+1 (`to`).
    fn prepare(&self, from: &HoverSample<T>, to: &HoverSample<T>) -> Result<Self::Prepared, Error>;
    /// Learns from a prepared update; writes the prior innovations of this model's outputs
    /// into `innovation` (the other entries are left alone).
    fn apply(&mut self, prepared: &Self::Prepared, innovation: &mut HoverState<T>);
    /// Writes this model's one-step prediction of sample k+1 from sample k into `next`.
    fn predict(&self, from: &HoverSample<T>, next: &mut HoverState<T>) -> Result<(), Error>;
    /// Back to θ(0) = 0, P(0) = αI.
    fn reset(&mut self);
    /// Everything learnt.
    fn export(&self) -> Self::State;
    /// Warm start from an exported state. On `Err` nothing changed.
    fn import(&mut self, state: &Self::State) -> Result<(), Error>;
}

/// Consequent structure of the translational model.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum VelocityStructure {
    /// Eq. 27: per rule `α1` (thrust along the rotor axis `R e2`, all three outputs) and `α2`
    /// (weight, `v_y` only). `D = 2`.
    Paper,
}

impl VelocityStructure {
    /// Consequent terms per rule.
    pub const fn terms(self) -> usize {
        match self {
            Self::Paper => 2,
        }
    }
}

/// The body "up" axis `j_b` in inertial paper axes: `R e2 = [sφcψ − cφsθsψ, cφcθ, sφsψ + cφsθcψ]`
/// (the column of R that Eq. 27 uses; NOTES.md item 1).
pub fn rotor_axis<T: Real>(roll: T, pitch: T, yaw: T) -> [T; 3] {
    let (sf, cf) = (roll.sin(), roll.cos());
    let (st, ct) = (pitch.sin(), pitch.cos());
    let (sp, cp) = (yaw.sin(), yaw.cos());
    [sf * cp - cf * st * sp, cf * ct, sf * sp + cf * st * cp]
}

/// Translational model (Eq. 27): premise `v^s(k)`, three outputs `v_x, v_y, v_z` sharing θ.
#[derive(Clone, Debug, PartialEq)]
pub struct VelocityModel<T, const R: usize, const D: usize, const N: usize, const NP: usize> {
    ts: TsRls<T, 3, R, D, N, NP>,
    structure: VelocityStructure,
}

impl<T: Real, const R: usize, const D: usize, const N: usize, const NP: usize>
    VelocityModel<T, R, D, N, NP>
{
    /// A model over the given rule base (premise `[v_x v_y v_z]`, m/s).
    pub fn new(
        rules: RuleBase<T, 3, R>,
        structure: VelocityStructure,
        config: RlsConfig<T>,
    ) -> Result<Self, Error> {
        if structure.terms() != D {
            return Err(ConfigError::ConsequentTerms {
                needed: structure.terms() as u8,
                found: D as u8,
            }
            .into());
        }
        Ok(Self {
            ts: TsRls::new(rules, config)?,
            structure,
        })
    }

    /// The underlying TS model (rule base, parameters, covariance).
    pub fn ts(&self) -> &TsRls<T, 3, R, D, N, NP> {
        &self.ts
    }

    /// The consequent terms `Δ` of the outputs `v_x, v_y, v_z` at sample k.
    pub fn terms(&self, s: &HoverSample<T>) -> [[T; D]; 3] {
        let mut terms = [[T::zero(); D]; 3];
        let a = &s.attitude;
        let e = rotor_axis(a.roll, a.pitch, a.yaw);
        match self.structure {
            VelocityStructure::Paper => {
                for (out, (t, &ei)) in terms.iter_mut().zip(e.iter()).enumerate() {
                    if let Some(x) = t.get_mut(0) {
                        *x = ei * s.controls.col;
                    }
                    if out == 1 {
                        if let Some(x) = t.get_mut(1) {
                            *x = T::one();
                        }
                    }
                }
            }
        }
        terms
    }
}

impl<T: Real, const R: usize, const D: usize, const N: usize, const NP: usize> StateModel<T>
    for VelocityModel<T, R, D, N, NP>
{
    type Prepared = Prepared<T, N, 3>;
    type State = RlsState<T, N, NP>;

    fn prepare(&self, from: &HoverSample<T>, to: &HoverSample<T>) -> Result<Self::Prepared, Error> {
        let [x0, y0, z0] = from.velocity;
        let [x1, y1, z1] = to.velocity;
        self.ts.prepare(
            &from.velocity,
            &self.terms(from),
            &[x1 - x0, y1 - y0, z1 - z0],
        )
    }

    fn apply(&mut self, prepared: &Self::Prepared, innovation: &mut HoverState<T>) {
        self.ts.apply(prepared);
        innovation.velocity = prepared.innovations;
    }

    fn predict(&self, from: &HoverSample<T>, next: &mut HoverState<T>) -> Result<(), Error> {
        let terms = self.terms(from);
        let mut out = from.velocity;
        for (o, t) in out.iter_mut().zip(terms.iter()) {
            *o += self.ts.predict(&from.velocity, t)?;
        }
        next.velocity = out;
        Ok(())
    }

    fn reset(&mut self) {
        self.ts.reset();
    }

    fn export(&self) -> Self::State {
        self.ts.export()
    }

    fn import(&mut self, state: &Self::State) -> Result<(), Error> {
        self.ts.import(state)
    }
}

/// Which body rate an angular model predicts.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum RateAxis {
    /// q̂, Eq. 28: `Δ = [r·p, u_lon·u_col]`.
    Pitch,
    /// r̂, Eq. 29: `Δ = [q·p, u_ped]`.
    Yaw,
    /// p̂, Eq. 30: `Δ = [q·r, u_lat·u_col]`.
    Roll,
}

impl RateAxis {
    /// Index of this rate in `[q r p]`.
    pub const fn index(self) -> usize {
        match self {
            Self::Pitch => 0,
            Self::Yaw => 1,
            Self::Roll => 2,
        }
    }
}

/// Consequent structure of an angular model.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum RateStructure {
    /// Eqs. 28–30: per rule an inertia-coupling coefficient `𝕀^i` (gyroscopic product of
    /// the other two rates) and a control gain `γ^i`. `D = 2`.
    Paper,
}

impl RateStructure {
    /// Consequent terms per rule.
    pub const fn terms(self) -> usize {
        match self {
            Self::Paper => 2,
        }
    }
}

/// An angular model (Eqs. 28–30): premise `[q r p](k)` (deg/s), one output.
#[derive(Clone, Debug, PartialEq)]
pub struct RateModel<T, const R: usize, const D: usize, const N: usize, const NP: usize> {
    ts: TsRls<T, 3, R, D, N, NP>,
    axis: RateAxis,
    structure: RateStructure,
}

impl<T: Real, const R: usize, const D: usize, const N: usize, const NP: usize>
    RateModel<T, R, D, N, NP>
{
    /// A model of one body rate over the given rule base (premise `[q r p]`, deg/s).
    pub fn new(
        axis: RateAxis,
        rules: RuleBase<T, 3, R>,
        structure: RateStructure,
        config: RlsConfig<T>,
    ) -> Result<Self, Error> {
        if structure.terms() != D {
            return Err(ConfigError::ConsequentTerms {
                needed: structure.terms() as u8,
                found: D as u8,
            }
            .into());
        }
        Ok(Self {
            ts: TsRls::new(rules, config)?,
            axis,
            structure,
        })
    }

    /// The underlying TS model (rule base, parameters, covariance).
    pub fn ts(&self) -> &TsRls<T, 3, R, D, N, NP> {
        &self.ts
    }

    /// Which rate this model predicts.
    pub fn axis(&self) -> RateAxis {
        self.axis
    }

    /// The consequent terms `Δ` at sample k.
    pub fn terms(&self, s: &HoverSample<T>) -> [T; D] {
        let [q, r, p] = s.rates;
        let u = &s.controls;
        let paper = match self.axis {
            RateAxis::Pitch => [r * p, u.lon * u.col],
            RateAxis::Yaw => [q * p, u.ped],
            RateAxis::Roll => [q * r, u.lat * u.col],
        };
        let mut terms = [T::zero(); D];
        match self.structure {
            RateStructure::Paper => {
                for (t, x) in terms.iter_mut().zip(paper) {
                    *t = x;
                }
            }
        }
        terms
    }

    fn rate(&self, s: &HoverSample<T>) -> T {
        s.rates
            .get(self.axis.index())
            .copied()
            .unwrap_or_else(T::zero)
    }
}

impl<T: Real, const R: usize, const D: usize, const N: usize, const NP: usize> StateModel<T>
    for RateModel<T, R, D, N, NP>
{
    type Prepared = Prepared<T, N, 1>;
    type State = RlsState<T, N, NP>;

    fn prepare(&self, from: &HoverSample<T>, to: &HoverSample<T>) -> Result<Self::Prepared, Error> {
        self.ts.prepare(
            &from.rates,
            &[self.terms(from)],
            &[self.rate(to) - self.rate(from)],
        )
    }

    fn apply(&mut self, prepared: &Self::Prepared, innovation: &mut HoverState<T>) {
        self.ts.apply(prepared);
        if let Some(slot) = innovation.rates.get_mut(self.axis.index()) {
            let [e] = prepared.innovations;
            *slot = e;
        }
    }

    fn predict(&self, from: &HoverSample<T>, next: &mut HoverState<T>) -> Result<(), Error> {
        let increment = self.ts.predict(&from.rates, &self.terms(from))?;
        if let Some(slot) = next.rates.get_mut(self.axis.index()) {
            *slot = self.rate(from) + increment;
        }
        Ok(())
    }

    fn reset(&mut self) {
        self.ts.reset();
    }

    fn export(&self) -> Self::State {
        self.ts.export()
    }

    fn import(&mut self, state: &Self::State) -> Result<(), Error> {
        self.ts.import(state)
    }
}
