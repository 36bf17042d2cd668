//! Golden runs: fixed, platform-independent inputs and the identifiers' outputs as hex bits.
//!
//! The inputs come from integer arithmetic and `f32` additions and multiplications only, so
//! they are the same bits on every machine. The expected outputs live in `core/tests/data/`;
//! the host build (debug and release, with the core's `std` feature), the core's own tests
//! (without `std`) and the firmware under QEMU all have to reproduce them exactly.
//!
//! It lives with the core's tests so that they compile and pass from the published package
//! (a support crate would be a path dev-dependency, which `cargo package` drops); the tests
//! and benchmarks crate `host-tests` compiles it too (`#[path]`, tests → core's test support),
//! so it uses nothing but `rotorid` and `alloc`.

extern crate alloc;
use alloc::format;
use alloc::string::String;
use alloc::vec::Vec;

use rotorid::hover::{flight_sets, Attitude, Controls, HoverSample, StateModel};
use rotorid::{
    ExtendedFuzzyIdentifier, ExtendedPlainIdentifier, FlightIdentifier, HoverConfig,
    HoverIdentifier, PaperFuzzyIdentifier, PaperPlainIdentifier, Real,
};

/// xorshift64: deterministic integers.
struct XorShift(u64);

impl XorShift {
    fn next_u64(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }
    /// Uniform in [−1, 1) from 24 bits: exact in f32.
    fn uniform(&mut self) -> f32 {
        let bits = (self.next_u64() >> 40) as u32; // 24 bits
        (bits as f32) * (1.0 / 8_388_608.0) - 1.0
    }
}

/// `n` samples at 50 Hz: every signal relaxes towards a target redrawn every 40 samples, so
/// the run crosses the hover region and Table 3's shoulders.
pub fn inputs(n: usize, seed: u64) -> Vec<HoverSample<f32>> {
    let mut rng = XorShift(seed | 1);
    // [roll, pitch, yaw, vx, vy, vz, q, r, p, col, ped, lon, lat]
    let scale: [f32; 13] = [
        0.2, 0.15, 1.0, 1.5, 1.2, 1.5, 30.0, 40.0, 30.0, 0.1, 0.4, 0.3, 0.3,
    ];
    let mut x = [0.0f32; 13];
    let mut target = [0.0f32; 13];
    let mut out = Vec::with_capacity(n);
    for k in 0..n {
        if k % 40 == 0 {
            for (t, s) in target.iter_mut().zip(scale) {
                *t = rng.uniform() * s;
            }
        }
        for (xi, ti) in x.iter_mut().zip(target) {
            *xi += (ti - *xi) * 0.1;
        }
        out.push(HoverSample {
            time_us: 1_000_000 + 20_000 * k as u64,
            attitude: Attitude {
                roll: x[0],
                pitch: x[1],
                yaw: x[2],
            },
            velocity: [x[3], x[4], x[5]],
            rates: [x[6], x[7], x[8]],
            controls: Controls {
                col: 0.5 + x[9],
                ped: x[10],
                lon: x[11],
                lat: x[12],
            },
        });
    }
    out
}

/// Converts the f32 inputs to another scalar (exact for f64).
pub fn convert<T: Real>(s: &HoverSample<f32>) -> HoverSample<T> {
    s.cast()
}

fn hex<T: Real>(x: T) -> String {
    if T::BYTES == 4 {
        format!("{:08x}", x.to_bits_u64())
    } else {
        format!("{:016x}", x.to_bits_u64())
    }
}

fn hex_all<T: Real>(xs: &[T]) -> String {
    xs.iter().map(|&x| hex(x)).collect::<Vec<_>>().join(" ")
}

/// Runs an identifier over the inputs; one line per step (predictions, innovations), then
/// every model's θ and covariance diagonal.
pub fn run<T, V, Q, R, P>(
    mut id: HoverIdentifier<T, V, Q, R, P>,
    inputs: &[HoverSample<f32>],
) -> String
where
    T: Real,
    V: StateModel<T> + HasDiagnostics<T>,
    Q: StateModel<T> + HasDiagnostics<T>,
    R: StateModel<T> + HasDiagnostics<T>,
    P: StateModel<T> + HasDiagnostics<T>,
{
    let mut out = String::new();
    for (k, s) in inputs.iter().enumerate() {
        let step = match id.step(&convert::<T>(s)) {
            Ok(step) => step,
            Err(e) => return format!("{out}error at step {k}: {e}\n"),
        };
        let inn = step
            .innovation
            .map(|i| i.to_array())
            .unwrap_or([T::zero(); 6]);
        out += &format!(
            "step {k} pred {} inn {}\n",
            hex_all(&step.prediction.to_array()),
            hex_all(&inn)
        );
    }
    for (name, theta, diag) in [
        (
            "velocity",
            id.velocity_model().theta(),
            id.velocity_model().diagonal(),
        ),
        (
            "pitch",
            id.pitch_model().theta(),
            id.pitch_model().diagonal(),
        ),
        ("yaw", id.yaw_model().theta(), id.yaw_model().diagonal()),
        ("roll", id.roll_model().theta(), id.roll_model().diagonal()),
    ] {
        out += &format!("{name} theta {}\n", hex_all(&theta));
        out += &format!("{name} pdiag {}\n", hex_all(&diag));
    }
    out
}

/// θ and diag(P) of a model, as vectors (for reports that do not know the sizes).
pub trait HasDiagnostics<T> {
    /// Parameters θ.
    fn theta(&self) -> Vec<T>;
    /// Diagonal of P.
    fn diagonal(&self) -> Vec<T>;
}

impl<T: Real, const R: usize, const D: usize, const N: usize, const NP: usize> HasDiagnostics<T>
    for rotorid::hover::VelocityModel<T, R, D, rotorid::ts::TsRls<T, 3, R, D, N, NP>>
{
    fn theta(&self) -> Vec<T> {
        self.ts().rls().parameters().to_vec()
    }
    fn diagonal(&self) -> Vec<T> {
        self.ts().rls().covariance_diagonal().to_vec()
    }
}

impl<T: Real, const R: usize, const D: usize, const N: usize, const NP: usize> HasDiagnostics<T>
    for rotorid::hover::RateModel<T, R, D, rotorid::ts::TsRls<T, 3, R, D, N, NP>>
{
    fn theta(&self) -> Vec<T> {
        self.ts().rls().parameters().to_vec()
    }
    fn diagonal(&self) -> Vec<T> {
        self.ts().rls().covariance_diagonal().to_vec()
    }
}

macro_rules! local_diagnostics {
    ($model:ident) => {
        /// Rule by rule: θ_1, θ_2, … and their covariance diagonals.
        impl<T: Real, const R: usize, const D: usize, const DP: usize> HasDiagnostics<T>
            for rotorid::hover::$model<T, R, D, rotorid::ts::local::LocalTsRls<T, 3, R, D, DP>>
        {
            fn theta(&self) -> Vec<T> {
                (0..R)
                    .filter_map(|i| self.ts().rule(i))
                    .flat_map(|r| r.parameters().to_vec())
                    .collect()
            }
            fn diagonal(&self) -> Vec<T> {
                (0..R)
                    .filter_map(|i| self.ts().rule(i))
                    .flat_map(|r| r.covariance_diagonal().collect::<Vec<_>>())
                    .collect()
            }
        }
    };
}
local_diagnostics!(VelocityModel);
local_diagnostics!(RateModel);

/// Steps of every golden run.
pub const STEPS: usize = 400;
/// Seed of every golden run.
pub const SEED: u64 = 0x0007_07e1_d5ee_d001;

/// The golden cases: (file name in `core/tests/data/`, output).
pub fn cases() -> Vec<(&'static str, String)> {
    let inp = inputs(STEPS, SEED);
    let fuzzy = |c: HoverConfig<f32>| PaperFuzzyIdentifier::<f32>::paper_fuzzy(c);
    let mut v = Vec::new();
    match fuzzy(HoverConfig::default()) {
        Ok(id) => v.push(("golden_fuzzy_f32_ud.txt", run(id, &inp))),
        Err(e) => v.push(("golden_fuzzy_f32_ud.txt", format!("{e}"))),
    }
    match fuzzy(HoverConfig::paper()) {
        Ok(id) => v.push(("golden_fuzzy_f32_paper.txt", run(id, &inp))),
        Err(e) => v.push(("golden_fuzzy_f32_paper.txt", format!("{e}"))),
    }
    match PaperPlainIdentifier::<f32>::paper_plain(HoverConfig::default()) {
        Ok(id) => v.push(("golden_plain_f32_ud.txt", run(id, &inp))),
        Err(e) => v.push(("golden_plain_f32_ud.txt", format!("{e}"))),
    }
    match PaperFuzzyIdentifier::<f64>::paper_fuzzy(HoverConfig::default()) {
        Ok(id) => v.push(("golden_fuzzy_f64_ud.txt", run(id, &inp))),
        Err(e) => v.push(("golden_fuzzy_f64_ud.txt", format!("{e}"))),
    }
    match ExtendedFuzzyIdentifier::<f32>::extended_fuzzy(HoverConfig::default()) {
        Ok(id) => v.push(("golden_extended_fuzzy_f32_ud.txt", run(id, &inp))),
        Err(e) => v.push(("golden_extended_fuzzy_f32_ud.txt", format!("{e}"))),
    }
    match ExtendedPlainIdentifier::<f32>::extended_plain(HoverConfig::default()) {
        Ok(id) => v.push(("golden_extended_plain_f32_ud.txt", run(id, &inp))),
        Err(e) => v.push(("golden_extended_plain_f32_ud.txt", format!("{e}"))),
    }
    match FlightIdentifier::<f32>::flight(HoverConfig::default(), flight_sets()) {
        Ok(id) => v.push(("golden_flight_f32_ud.txt", run(id, &inp))),
        Err(e) => v.push(("golden_flight_f32_ud.txt", format!("{e}"))),
    }
    match FlightIdentifier::<f64>::flight(HoverConfig::default(), flight_sets()) {
        Ok(id) => v.push(("golden_flight_f64_ud.txt", run(id, &inp))),
        Err(e) => v.push(("golden_flight_f64_ud.txt", format!("{e}"))),
    }
    v
}

/// Compares every case with its file in `dir`; writes the files instead when the
/// environment variable `ROTORID_BLESS` is set. Returns the first difference, with its line.
pub fn check(dir: &std::path::Path) -> Result<(), String> {
    let bless = std::env::var_os("ROTORID_BLESS").is_some();
    for (name, got) in cases() {
        let path = dir.join(name);
        if bless {
            std::fs::write(&path, &got).map_err(|e| format!("{}: {e}", path.display()))?;
            continue;
        }
        let want = std::fs::read_to_string(&path).map_err(|e| {
            format!(
                "{}: {e} (run with ROTORID_BLESS=1 to create)",
                path.display()
            )
        })?;
        if let Some((i, (w, g))) = want
            .lines()
            .zip(got.lines())
            .enumerate()
            .find(|(_, (w, g))| w != g)
        {
            return Err(format!("{name}:{}: expected\n  {w}\ngot\n  {g}", i + 1));
        }
        if want.lines().count() != got.lines().count() {
            return Err(format!(
                "{name}: {} lines expected, {} produced",
                want.lines().count(),
                got.lines().count()
            ));
        }
    }
    Ok(())
}
