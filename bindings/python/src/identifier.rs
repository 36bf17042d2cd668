//! The identifiers of the C interface as Python classes: one `Identifier` class holding any
//! of the eight kinds (the C interface's `ROTORID_KIND_*`, with the same codes, default
//! settings and premise sets as `rotorid_init` with NULL `config` and `sets`), so that an
//! export is byte for byte the C interface's (and the firmware's) for the same samples.
//!
//! Samples are in the core's axes and units (`rotorid::HoverSample`, as `rotorid_sample_t`):
//! time (µs), attitude `[φ θ ψ]` (rad, ZYX Euler), velocity `[v_x v_y v_z]` (m/s, paper axes:
//! x east, y up, z south), rates `[q r p]` (deg/s), controls `[u_col u_ped u_lon u_lat]`.

use pyo3::prelude::*;
use pyo3::types::PyBytes;
use rotorid::hover::{
    flight_sets, table3, Attitude, Controls, GyroCompensation, HoverState, Scheduling,
};
use rotorid::snapshot::KindCode;
use rotorid::{
    DynIdentifier, ExtendedFuzzyIdentifier, ExtendedLocalIdentifier, ExtendedPlainIdentifier,
    FlightIdentifier, FlightPlainIdentifier, HoverConfig, HoverSample, PaperFuzzyIdentifier,
    PaperLocalIdentifier, PaperPlainIdentifier,
};

use crate::errors;

/// `compensate`'s `how`: `None` (damping on every rate), one name for every rate, or a
/// sequence of three names `[q r p]`.
fn compensation(how: Option<&Bound<'_, PyAny>>) -> PyResult<[GyroCompensation; 3]> {
    let one = |name: &str| match name {
        "damping" => Ok(GyroCompensation::Damping),
        "full" => Ok(GyroCompensation::Full),
        other => Err(errors::input(format!(
            "compensate: how {:?}; expected \"damping\" or \"full\"",
            other.chars().take(40).collect::<String>()
        ))),
    };
    let Some(how) = how else {
        return Ok([GyroCompensation::Damping; 3]);
    };
    if let Ok(name) = how.extract::<String>() {
        return Ok([one(&name)?; 3]);
    }
    match how.extract::<Vec<String>>() {
        Ok(names) if names.len() == 3 => Ok([one(&names[0])?, one(&names[1])?, one(&names[2])?]),
        _ => Err(errors::input(
            "compensate: how must be \"damping\", \"full\" or a list of three of them [q r p]",
        )),
    }
}

/// Floats of one sample in a `step_many` block: attitude 3, velocity 3, rates 3, controls 4.
pub const FLOATS_PER_SAMPLE: usize = 13;

/// One identifier of any kind, behind the core's dyn-compatible [`DynIdentifier`], with its
/// name and kind code.
struct Any {
    name: &'static str,
    code: u32,
    id: Box<dyn DynIdentifier + Send + Sync>,
}

/// Every kind: its name, type and constructor (the list `build` chooses from). The codes are
/// the core's ([`KindCode`]), which the C interface's `ROTORID_KIND_*` equal.
macro_rules! kinds {
    ($($name:literal, $T:ty, $new:expr;)*) => {
        /// The kind names, in kind code order.
        pub const KIND_NAMES: &[&str] = &[$($name),*];

        fn build(name: &str) -> Option<Result<Any, rotorid::Error>> {
            match name {
                $($name => Some($new(HoverConfig::default()).map(|id: $T| Any {
                    name: $name,
                    code: <$T as KindCode>::KIND,
                    id: Box::new(id),
                })),)*
                _ => None,
            }
        }
    };
}

kinds! {
    "flight", FlightIdentifier<f32>, |c| FlightIdentifier::<f32>::flight(c, flight_sets());
    "flight_plain", FlightPlainIdentifier<f32>, FlightPlainIdentifier::<f32>::flight_plain;
    "paper_fuzzy", PaperFuzzyIdentifier<f32>, PaperFuzzyIdentifier::<f32>::paper_fuzzy;
    "paper_plain", PaperPlainIdentifier<f32>, PaperPlainIdentifier::<f32>::paper_plain;
    "extended_fuzzy", ExtendedFuzzyIdentifier<f32>, ExtendedFuzzyIdentifier::<f32>::extended_fuzzy;
    "extended_plain", ExtendedPlainIdentifier<f32>, ExtendedPlainIdentifier::<f32>::extended_plain;
    "paper_local", PaperLocalIdentifier<f32>, PaperLocalIdentifier::<f32>::paper_local;
    "extended_local", ExtendedLocalIdentifier<f32>, ExtendedLocalIdentifier::<f32>::extended_local;
}

fn sample(
    time_us: u64,
    attitude: [f32; 3],
    velocity: [f32; 3],
    rates: [f32; 3],
    controls: [f32; 4],
) -> HoverSample<f32> {
    let [roll, pitch, yaw] = attitude;
    let [col, ped, lon, lat] = controls;
    HoverSample {
        time_us,
        attitude: Attitude { roll, pitch, yaw },
        velocity,
        rates,
        controls: Controls { col, ped, lon, lat },
    }
}

fn state(s: &HoverState<f32>) -> [f32; 6] {
    let [a, b, c] = s.velocity;
    let [q, r, p] = s.rates;
    [a, b, c, q, r, p]
}

/// One model's premise as `Identifier`'s `premises` give it: the speed its three rules are
/// on, and their centres and spreads (m/s: left shoulder, Gaussian, right shoulder).
type ModelPremise = (String, [f32; 3], [f32; 3]);

/// The flight kind with each model's (velocity, q̂, r̂, p̂) rules on the speed and sets
/// `premises` names (`FlightIdentifier::flight_scheduled`, as the C interface's
/// `rotorid_init_flight_scheduled`): what `flight selected` chose.
fn flight_scheduled(premises: &[ModelPremise]) -> PyResult<Any> {
    let models: &[ModelPremise; 4] = premises.try_into().map_err(|_| {
        errors::input(format!(
            "premises: {} models; expected 4 (velocity, q, r, p)",
            premises.len()
        ))
    })?;
    let on = |name: &str| match name {
        "speed" => Ok(Scheduling::Speed),
        "side_speed" => Ok(Scheduling::SideSpeed),
        "vertical_speed" => Ok(Scheduling::VerticalSpeed),
        other => Err(errors::input(format!(
            "premises: speed {:?}; expected \"speed\", \"side_speed\" or \"vertical_speed\"",
            other.chars().take(40).collect::<String>()
        ))),
    };
    let [a, b, c, d] = models;
    let schedules = [on(&a.0)?, on(&b.0)?, on(&c.0)?, on(&d.0)?];
    let sets = models
        .each_ref()
        .map(|(_, centre, spread)| table3::shoulder_sets(*centre, *spread));
    let id = FlightIdentifier::<f32>::flight_scheduled(HoverConfig::default(), sets, schedules)
        .map_err(|e| errors::core(e, "premises"))?;
    Ok(Any {
        name: "flight",
        code: <FlightIdentifier<f32> as KindCode>::KIND,
        id: Box::new(id),
    })
}

impl Any {
    fn export(&self) -> Option<Vec<u8>> {
        self.id.snapshot_vec(self.code).ok()
    }
    fn import(&mut self, bytes: &[u8]) -> Result<(), rotorid::Error> {
        self.id.read_snapshot(self.code, bytes)
    }
}

/// A hover identifier of one kind (`kind`: one of `KINDS`), stepping sample by sample.
#[pyclass(subclass, module = "rotorid._rotorid")]
pub struct Identifier {
    inner: Any,
}

/// The outcome of `step_many`: predictions and innovations (n × 6 f32 each, NaN where the
/// step made none) and the error that stopped it, if any.
type Many = (Vec<f32>, Vec<f32>, Option<(usize, rotorid::Error)>);

fn step_block(inner: &mut Any, times: &[u8], floats: &[u8]) -> Many {
    let n = times.len() / 8;
    let mut predictions = Vec::with_capacity(n * 6);
    let mut innovations = Vec::with_capacity(n * 6);
    let rows = times
        .chunks_exact(8)
        .zip(floats.chunks_exact(4 * FLOATS_PER_SAMPLE));
    for (k, (t, f)) in rows.enumerate() {
        let mut t8 = [0u8; 8];
        t8.copy_from_slice(t);
        let mut v = [0f32; FLOATS_PER_SAMPLE];
        for (x, b) in v.iter_mut().zip(f.chunks_exact(4)) {
            let mut b4 = [0u8; 4];
            b4.copy_from_slice(b);
            *x = f32::from_le_bytes(b4);
        }
        let [r, p, y, vx, vy, vz, q, rr, pp, c, pe, lo, la] = v;
        let s = sample(
            u64::from_le_bytes(t8),
            [r, p, y],
            [vx, vy, vz],
            [q, rr, pp],
            [c, pe, lo, la],
        );
        match inner.id.step(&s) {
            Ok(out) => {
                predictions.extend(state(&out.prediction));
                match &out.innovation {
                    Some(i) => innovations.extend(state(i)),
                    None => innovations.extend([f32::NAN; 6]),
                }
            }
            Err(e) => return (predictions, innovations, Some((k, e))),
        }
    }
    (predictions, innovations, None)
}

fn f32_bytes(values: &[f32]) -> Vec<u8> {
    values.iter().flat_map(|x| x.to_le_bytes()).collect()
}

#[pymethods]
impl Identifier {
    /// A new identifier of `kind` ("flight", "flight_plain", "paper_fuzzy", "paper_plain",
    /// "extended_fuzzy", "extended_plain", "paper_local", "extended_local") with the default
    /// settings (U-D RLS, α = 10⁶, λ = 1, 50 Hz).
    ///
    /// `premises` (the flight kind only): per model (velocity, q̂, r̂, p̂) the speed its three
    /// rules are on ("speed", "side_speed" for a rate model, "vertical_speed") and their
    /// centres and spreads (m/s), as `rotorid_init_flight_scheduled` takes them.
    #[new]
    #[pyo3(signature = (kind, premises = None))]
    fn new(kind: &str, premises: Option<Vec<ModelPremise>>) -> PyResult<Self> {
        if let Some(premises) = premises {
            if kind != "flight" {
                return Err(errors::input(format!(
                    "premises are the flight kind's, not {:?}'s",
                    kind.chars().take(40).collect::<String>()
                )));
            }
            return flight_scheduled(&premises).map(|inner| Self { inner });
        }
        match build(kind) {
            Some(Ok(inner)) => Ok(Self { inner }),
            Some(Err(e)) => Err(errors::core(e, kind)),
            None => Err(errors::input(format!(
                "unknown identifier kind {:?}; expected one of {}",
                kind.chars().take(40).collect::<String>(),
                KIND_NAMES.join(", ")
            ))),
        }
    }

    /// The kind's name.
    #[getter]
    fn kind(&self) -> &'static str {
        self.inner.name
    }

    /// The kind's code in the C interface (`ROTORID_KIND_*`).
    #[getter]
    fn kind_code(&self) -> u32 {
        self.inner.code
    }

    /// Bytes of an export (`ROTORID_<KIND>_EXPORT_SIZE`).
    #[getter]
    fn export_size(&self) -> usize {
        self.inner.id.snapshot_size()
    }

    /// Takes one sample; returns `(prediction, innovation)`: the one-step prediction of the
    /// next sample's state `[v_x v_y v_z q r p]` (m/s, deg/s) and the prior innovation of
    /// this update (`None` when the step only started a sample chain).
    fn step(
        &mut self,
        time_us: u64,
        attitude: [f32; 3],
        velocity: [f32; 3],
        rates: [f32; 3],
        controls: [f32; 4],
    ) -> PyResult<([f32; 6], Option<[f32; 6]>)> {
        let s = sample(time_us, attitude, velocity, rates, controls);
        let out = self.inner.id.step(&s).map_err(|e| errors::core(e, ""))?;
        Ok((state(&out.prediction), out.innovation.as_ref().map(state)))
    }

    /// Restarts the sample chain at this sample (after a gap) without learning; returns the
    /// measured state.
    fn resume(
        &mut self,
        time_us: u64,
        attitude: [f32; 3],
        velocity: [f32; 3],
        rates: [f32; 3],
        controls: [f32; 4],
    ) -> PyResult<[f32; 6]> {
        let s = sample(time_us, attitude, velocity, rates, controls);
        let out = self.inner.id.resume(&s).map_err(|e| errors::core(e, ""))?;
        Ok(state(&out))
    }

    /// Removes from the rate models' parameters the bias of the gyros' white noise
    /// `gyro_noise` σ `[q r p]` (deg/s), as the C interface's `rotorid_compensate_each`:
    /// `how` is "damping" (the damping term's noise; the default) or "full" (the
    /// second-order term's too), one for every rate or a list of three `[q r p]`. Returns
    /// `(compensated, refused)`, the rules whose parameters were replaced and those left as
    /// they were (too little information, or the compensated rate would be unstable). These
    /// are the parameters to free-run with (`identify` flies them); the learnt ones are the
    /// better one-step predictor, so compensate a copy (`import_` of an `export`) and keep
    /// learning on the original. Raises `InputError` for an unknown `how`, a `CoreError`
    /// subclass for a σ the core refuses (negative, not finite), leaving the identifier
    /// unchanged.
    #[pyo3(signature = (gyro_noise, how = None))]
    fn compensate(
        &mut self,
        gyro_noise: [f32; 3],
        how: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<(u16, u16)> {
        let how = compensation(how)?;
        let done = self
            .inner
            .id
            .compensate_each(&gyro_noise, how)
            .map_err(|e| errors::core(e, "compensate"))?;
        Ok((done.compensated, done.refused))
    }

    /// Forgets everything learnt (the parameters back to their initial values).
    fn reset(&mut self) {
        self.inner.id.reset();
    }

    /// Steps over a block: `times` n little-endian u64 (µs), `floats` n × 13 little-endian
    /// f32 (attitude, velocity, rates, controls). Returns `(predictions, innovations)` as
    /// bytes of n × 6 f32 (NaN innovations where a step only started a chain); raises at the
    /// first refused sample (the steps before it stay learnt). The GIL is released while stepping. Called by `step_many`.
    fn _step_block<'py>(
        &mut self,
        py: Python<'py>,
        times: &[u8],
        floats: &[u8],
    ) -> PyResult<(Bound<'py, PyBytes>, Bound<'py, PyBytes>)> {
        let n = times.len() / 8;
        if !times.len().is_multiple_of(8) || floats.len() != n * 4 * FLOATS_PER_SAMPLE {
            return Err(errors::input(format!(
                "step block: {} time bytes and {} float bytes do not make whole samples",
                times.len(),
                floats.len()
            )));
        }
        let inner = &mut self.inner;
        let (pred, innov, err) = py.detach(|| step_block(inner, times, floats));
        if let Some((k, e)) = err {
            return Err(errors::core(e, &format!("sample {k}")));
        }
        Ok((
            PyBytes::new(py, &f32_bytes(&pred)),
            PyBytes::new(py, &f32_bytes(&innov)),
        ))
    }

    /// The export (warm start across flights): the C interface's `rotorid_export` bytes,
    /// header "RIDX", format version 2, the kind code, every model's RLS state, CRC-32.
    fn export<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyBytes>> {
        match self.inner.export() {
            Some(bytes) => Ok(PyBytes::new(py, &bytes)),
            None => Err(errors::input(
                "export: the buffer is smaller than the export",
            )),
        }
    }

    /// Imports an export of the same kind (length, CRC, header and every value are checked
    /// before anything changes; on an error the identifier is unchanged).
    fn import_(&mut self, data: &[u8]) -> PyResult<()> {
        self.inner
            .import(data)
            .map_err(|e| errors::core(e, "import"))
    }

    fn __repr__(&self) -> String {
        format!("<rotorid identifier kind={:?}>", self.inner.name)
    }
}
