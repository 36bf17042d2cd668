//! The identifier kinds of the C interface: codes, sizes, how each is built, and the calls any
//! kind answers.

use rotorid::hover::{flight_sets, table3, AnyAttitude, Scheduling, StateModel};
use rotorid::{
    DynIdentifier, ExtendedFuzzyIdentifier, ExtendedLocalIdentifier, ExtendedPlainIdentifier,
    FlightIdentifier, FlightPlainIdentifier, HoverConfig, HoverIdentifier, PaperFuzzyIdentifier,
    PaperLocalIdentifier, PaperPlainIdentifier,
};

use rotorid::record;
use rotorid::snapshot::{Snapshot, SnapshotState};

use crate::types::*;

/// The flight default: three speed rules per model (the rates on the forward speed, the
/// translational model on the horizontal speed), local learning, the extended flight
/// structures (`rotorid::FlightIdentifier`).
pub const ROTORID_KIND_FLIGHT: u32 = 1;
/// The flight structures with one rule (`rotorid::FlightPlainIdentifier`).
pub const ROTORID_KIND_FLIGHT_PLAIN: u32 = 2;
/// The paper's fuzzy identifier (Table 3 sets, global RLS; `rotorid::PaperFuzzyIdentifier`).
pub const ROTORID_KIND_PAPER_FUZZY: u32 = 3;
/// The paper's plain identifier (one rule; `rotorid::PaperPlainIdentifier`).
pub const ROTORID_KIND_PAPER_PLAIN: u32 = 4;
/// Extended structures, Table 3 sets, global RLS (`rotorid::ExtendedFuzzyIdentifier`).
pub const ROTORID_KIND_EXTENDED_FUZZY: u32 = 5;
/// Extended structures, one rule (`rotorid::ExtendedPlainIdentifier`).
pub const ROTORID_KIND_EXTENDED_PLAIN: u32 = 6;
/// The paper's structures and sets, learnt locally (`rotorid::PaperLocalIdentifier`).
pub const ROTORID_KIND_PAPER_LOCAL: u32 = 7;
/// Extended structures, Table 3 sets, learnt locally (`rotorid::ExtendedLocalIdentifier`).
pub const ROTORID_KIND_EXTENDED_LOCAL: u32 = 8;

/// Alignment every identifier's storage needs (bytes).
pub const ROTORID_STORAGE_ALIGN: usize = 8;

/// Storage bytes of `ROTORID_KIND_FLIGHT`.
pub const ROTORID_FLIGHT_STORAGE_SIZE: usize = 2984;
/// Storage bytes of `ROTORID_KIND_FLIGHT_PLAIN`.
pub const ROTORID_FLIGHT_PLAIN_STORAGE_SIZE: usize = 1664;
/// Storage bytes of `ROTORID_KIND_PAPER_FUZZY`.
pub const ROTORID_PAPER_FUZZY_STORAGE_SIZE: usize = 11280;
/// Storage bytes of `ROTORID_KIND_PAPER_PLAIN`.
pub const ROTORID_PAPER_PLAIN_STORAGE_SIZE: usize = 880;
/// Storage bytes of `ROTORID_KIND_EXTENDED_FUZZY`.
pub const ROTORID_EXTENDED_FUZZY_STORAGE_SIZE: usize = 27248;
/// Storage bytes of `ROTORID_KIND_EXTENDED_PLAIN`.
pub const ROTORID_EXTENDED_PLAIN_STORAGE_SIZE: usize = 1240;
/// Storage bytes of `ROTORID_KIND_PAPER_LOCAL`.
pub const ROTORID_PAPER_LOCAL_STORAGE_SIZE: usize = 3104;
/// Storage bytes of `ROTORID_KIND_EXTENDED_LOCAL`.
pub const ROTORID_EXTENDED_LOCAL_STORAGE_SIZE: usize = 4872;

/// Export bytes of `ROTORID_KIND_FLIGHT`.
pub const ROTORID_FLIGHT_EXPORT_SIZE: usize = 1900;
/// Export bytes of `ROTORID_KIND_FLIGHT_PLAIN`.
pub const ROTORID_FLIGHT_PLAIN_EXPORT_SIZE: usize = 644;
/// Export bytes of `ROTORID_KIND_PAPER_FUZZY`.
pub const ROTORID_PAPER_FUZZY_EXPORT_SIZE: usize = 10524;
/// Export bytes of `ROTORID_KIND_PAPER_PLAIN`.
pub const ROTORID_PAPER_PLAIN_EXPORT_SIZE: usize = 128;
/// Export bytes of `ROTORID_KIND_EXTENDED_FUZZY`.
pub const ROTORID_EXTENDED_FUZZY_EXPORT_SIZE: usize = 26436;
/// Export bytes of `ROTORID_KIND_EXTENDED_PLAIN`.
pub const ROTORID_EXTENDED_PLAIN_EXPORT_SIZE: usize = 428;
/// Export bytes of `ROTORID_KIND_PAPER_LOCAL`.
pub const ROTORID_PAPER_LOCAL_EXPORT_SIZE: usize = 1780;
/// Export bytes of `ROTORID_KIND_EXTENDED_LOCAL`.
pub const ROTORID_EXTENDED_LOCAL_EXPORT_SIZE: usize = 3628;

/// Any identifier kind as the C interface calls it: the core's [`DynIdentifier`], for samples
/// whose attitude form the caller chooses per call.
pub(crate) type AnyKind = dyn DynIdentifier<AnyAttitude<f32>>;

/// The export size of an identifier type.
pub(crate) trait ExportSize {
    const EXPORT_SIZE: usize;
}

impl<V, Q, R, P> ExportSize for HoverIdentifier<f32, V, Q, R, P>
where
    V: StateModel<f32, State: SnapshotState>,
    Q: StateModel<f32, State: SnapshotState>,
    R: StateModel<f32, State: SnapshotState>,
    P: StateModel<f32, State: SnapshotState>,
{
    const EXPORT_SIZE: usize = <Self as Snapshot>::SNAPSHOT_SIZE;
}

/// Calls `$body` with `$I` the identifier type of kind code `$kind` (`$none` for an unknown
/// code): the one list of kinds every call dispatches through.
macro_rules! for_kind {
    ($kind:expr, $I:ident => $body:expr, _ => $none:expr) => {
        match $kind {
            ROTORID_KIND_FLIGHT => {
                type $I = rotorid::FlightIdentifier<f32>;
                $body
            }
            ROTORID_KIND_FLIGHT_PLAIN => {
                type $I = rotorid::FlightPlainIdentifier<f32>;
                $body
            }
            ROTORID_KIND_PAPER_FUZZY => {
                type $I = rotorid::PaperFuzzyIdentifier<f32>;
                $body
            }
            ROTORID_KIND_PAPER_PLAIN => {
                type $I = rotorid::PaperPlainIdentifier<f32>;
                $body
            }
            ROTORID_KIND_EXTENDED_FUZZY => {
                type $I = rotorid::ExtendedFuzzyIdentifier<f32>;
                $body
            }
            ROTORID_KIND_EXTENDED_PLAIN => {
                type $I = rotorid::ExtendedPlainIdentifier<f32>;
                $body
            }
            ROTORID_KIND_PAPER_LOCAL => {
                type $I = rotorid::PaperLocalIdentifier<f32>;
                $body
            }
            ROTORID_KIND_EXTENDED_LOCAL => {
                type $I = rotorid::ExtendedLocalIdentifier<f32>;
                $body
            }
            _ => $none,
        }
    };
}

pub(crate) use for_kind;

/// Bytes of a persistence record of `kind` (0 for an unknown kind): the export plus
/// `ROTORID_RECORD_OVERHEAD` (`docs/c-interface.md`, "Keeping the model across resets").
#[no_mangle]
pub extern "C" fn rotorid_record_size(kind: u32) -> usize {
    for_kind!(kind, I => record::size_of::<I>(), _ => 0)
}

/// Bytes of an export of `kind` (0 for an unknown kind).
#[no_mangle]
pub extern "C" fn rotorid_export_size(kind: u32) -> usize {
    for_kind!(kind, I => <I as ExportSize>::EXPORT_SIZE, _ => 0)
}

fn premise_sets(s: &rotorid_flight_sets_t) -> rotorid::rule_base::PremiseSets<f32> {
    table3::shoulder_sets(s.centre, s.spread)
}

/// The speed sets an init was given.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Sets<'a> {
    /// None: the kind's own (for the flight kind, `rotorid::hover::flight_sets`).
    Default,
    /// One list for the four models (`rotorid_init`'s `sets`).
    Shared(&'a rotorid_flight_sets_t),
    /// One list per model: velocity, q̂, r̂, p̂ (`rotorid_init_flight_per_model`).
    PerModel(&'a [rotorid_flight_sets_t; 4]),
    /// One list per model and the speed it is on (`rotorid_init_flight_scheduled`; only
    /// [`ScheduledFlight`] builds from it).
    Scheduled(&'a [rotorid_flight_sets_t; 4], [Scheduling; 4]),
}

impl Sets<'_> {
    /// `rotorid_init`'s `sets`: NULL for the defaults.
    ///
    /// # Safety
    /// `sets` is NULL or valid for reads for as long as the result is used.
    pub(crate) unsafe fn of<'a>(sets: *const rotorid_flight_sets_t) -> Sets<'a> {
        // SAFETY: the caller's contract.
        match unsafe { sets.as_ref() } {
            Some(s) => Sets::Shared(s),
            None => Sets::Default,
        }
    }
}

/// How each kind is built from the C settings.
pub(crate) trait Build: Sized {
    /// The core's constructor of the kind.
    fn build(config: HoverConfig<f32>, sets: Sets<'_>) -> Result<Self, rotorid::Error>;

    /// Builds straight into `out`: the identifier is never copied through the caller's
    /// frame (for the paper's fuzzy identifier that is 11 KiB of stack saved per copy).
    ///
    /// # Safety
    /// `out` is aligned and valid for a write of `Self`.
    #[inline(never)]
    unsafe fn build_into(
        config: HoverConfig<f32>,
        sets: Sets<'_>,
        out: *mut Self,
    ) -> Result<(), rotorid::Error> {
        // SAFETY: the caller's contract, alignment included. Told to the compiler, it writes
        // the storage with the word-aligned `memcpy`/`memclr` (without, it links the unaligned
        // `__aeabi_memclr` too: 208 B in the lean flight firmware).
        unsafe {
            core::hint::assert_unchecked(out.is_aligned());
            out.write(Self::build(config, sets)?);
        }
        Ok(())
    }
}

/// Kinds without premise sets of their own (`rotorid_init` refuses sets for them).
macro_rules! build_without_sets {
    ($($I:ty => $new:path),* $(,)?) => {$(
        impl Build for $I {
            fn build(
                config: HoverConfig<f32>,
                _: Sets<'_>,
            ) -> Result<Self, rotorid::Error> {
                $new(config)
            }
        }
    )*};
}

build_without_sets! {
    FlightPlainIdentifier<f32> => FlightPlainIdentifier::flight_plain,
    PaperFuzzyIdentifier<f32> => PaperFuzzyIdentifier::paper_fuzzy,
    PaperPlainIdentifier<f32> => PaperPlainIdentifier::paper_plain,
    ExtendedFuzzyIdentifier<f32> => ExtendedFuzzyIdentifier::extended_fuzzy,
    ExtendedPlainIdentifier<f32> => ExtendedPlainIdentifier::extended_plain,
    PaperLocalIdentifier<f32> => PaperLocalIdentifier::paper_local,
    ExtendedLocalIdentifier<f32> => ExtendedLocalIdentifier::extended_local,
}

impl Build for FlightIdentifier<f32> {
    fn build(config: HoverConfig<f32>, sets: Sets<'_>) -> Result<Self, rotorid::Error> {
        // One constructor for the three forms (`flight` is `flight_per_model` with the same
        // sets four times): a firmware that never passes per-model sets links no more code.
        let sets = match sets {
            Sets::Default => core::array::from_fn(|_| flight_sets()),
            Sets::Shared(s) => core::array::from_fn(|_| premise_sets(s)),
            // `Scheduled` is `ScheduledFlight`'s: here only its sets count.
            Sets::PerModel(each) | Sets::Scheduled(each, _) => each.each_ref().map(premise_sets),
        };
        FlightIdentifier::flight_per_model(config, sets)
    }
}

/// The flight kind's identifier as `rotorid_init_flight_scheduled` builds it
/// (`FlightIdentifier::flight_scheduled`): a type of its own so that only that init links
/// the constructor, and transparent, so that the storage holds a `FlightIdentifier` that
/// every other call of the kind takes as it is.
#[repr(transparent)]
pub(crate) struct ScheduledFlight(FlightIdentifier<f32>);

impl Build for ScheduledFlight {
    fn build(config: HoverConfig<f32>, sets: Sets<'_>) -> Result<Self, rotorid::Error> {
        // Only `rotorid_init_flight_scheduled` builds this type, always with `Scheduled`. Not
        // a call of `FlightIdentifier::build` for the other forms: a second caller leaves
        // that out of line, and the flight kind's init then copies the identifier through
        // its stack (4 292 → 12 900 B).
        let Sets::Scheduled(each, on) = sets else {
            return Err(rotorid::ConfigError::Dimensions.into());
        };
        FlightIdentifier::flight_scheduled(config, each.each_ref().map(premise_sets), on).map(Self)
    }
}

/// `rotorid_init_flight_scheduled`'s choice for a model: its three sets on the flight
/// default's speed, the horizontal speed for the velocity model and the forward speed for
/// the rate models (`rotorid::hover::Scheduling::Speed`).
pub const ROTORID_SCHEDULE_SPEED: u32 = 0;
/// `rotorid_init_flight_scheduled`'s choice for a rate model: its sets on the side speed
/// (heading frame, m/s; `rotorid::hover::Scheduling::SideSpeed`).
pub const ROTORID_SCHEDULE_SIDE_SPEED: u32 = 1;
/// `rotorid_init_flight_scheduled`'s choice for a model: its sets on the vertical speed (up,
/// m/s; `rotorid::hover::Scheduling::VerticalSpeed`).
pub const ROTORID_SCHEDULE_VERTICAL_SPEED: u32 = 2;

/// The core's scheduling of each `ROTORID_SCHEDULE_*` code; `None` when one is not a code.
pub(crate) fn scheduling(codes: &[u32; 4]) -> Option<[Scheduling; 4]> {
    let [v, q, r, p] = codes.map(|code| match code {
        ROTORID_SCHEDULE_SPEED => Some(Scheduling::Speed),
        ROTORID_SCHEDULE_SIDE_SPEED => Some(Scheduling::SideSpeed),
        ROTORID_SCHEDULE_VERTICAL_SPEED => Some(Scheduling::VerticalSpeed),
        _ => None,
    });
    Some([v?, q?, r?, p?])
}

#[cfg(test)]
mod tests {
    use super::*;
    use rotorid::snapshot::KindCode;

    /// The C codes are the core's (`rotorid::snapshot::KindCode`): a snapshot the CLI writes
    /// imports here under the same kind.
    #[test]
    fn the_kind_codes_are_the_cores() {
        assert_eq!(ROTORID_KIND_FLIGHT, FlightIdentifier::<f32>::KIND);
        assert_eq!(
            ROTORID_KIND_FLIGHT_PLAIN,
            FlightPlainIdentifier::<f32>::KIND
        );
        assert_eq!(ROTORID_KIND_PAPER_FUZZY, PaperFuzzyIdentifier::<f32>::KIND);
        assert_eq!(ROTORID_KIND_PAPER_PLAIN, PaperPlainIdentifier::<f32>::KIND);
        assert_eq!(
            ROTORID_KIND_EXTENDED_FUZZY,
            ExtendedFuzzyIdentifier::<f32>::KIND
        );
        assert_eq!(
            ROTORID_KIND_EXTENDED_PLAIN,
            ExtendedPlainIdentifier::<f32>::KIND
        );
        assert_eq!(ROTORID_KIND_PAPER_LOCAL, PaperLocalIdentifier::<f32>::KIND);
        assert_eq!(
            ROTORID_KIND_EXTENDED_LOCAL,
            ExtendedLocalIdentifier::<f32>::KIND
        );
    }
}
