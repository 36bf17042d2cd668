//! The snapshot format and the persistence record: round trips, A/B alternation, sequence
//! wrap-around, torn and foreign slots, and that nothing is imported on any refusal.
// Test code, outside `#[test]` functions: a panic here is a failed test (Cargo.toml's lints).
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::indexing_slicing)]

use embedded_storage::nor_flash::{ErrorType, NorFlash, NorFlashErrorKind, ReadNorFlash};
use rotorid::hover::{flight_sets, Attitude, Controls};
use rotorid::record::{self, RecordError, RecordInfo, Slot, Slots};
use rotorid::snapshot::{self, Snapshot};
use rotorid::{Error, FlightIdentifier, HoverConfig, HoverSample, PaperPlainIdentifier};

const KIND: u32 = 1;

fn sample(k: u32) -> HoverSample<f32> {
    let t = k as f32 * 0.02;
    let s = |w: f32, phase: f32| (w * t + phase).sin();
    let speed = 5.0 + 5.0 * s(1.6, 0.0);
    HoverSample {
        time_us: 1_000_000 + u64::from(k) * 20_000,
        attitude: Attitude {
            roll: 0.2 * s(0.9, 0.3),
            pitch: -0.05 + 0.15 * s(1.3, 1.0),
            yaw: 0.5 * s(0.3, 0.0),
        },
        velocity: [1.5 * s(2.1, 0.5), 1.2 * s(2.9, 0.0), -speed],
        rates: [30.0 * s(3.1, 0.0), 30.0 * s(2.3, 1.0), 30.0 * s(3.7, 2.0)],
        controls: Controls {
            col: 0.5 + 0.1 * s(0.7, 0.0),
            ped: 0.2 * s(2.3, 0.0),
            lon: 0.2 * s(1.9, 0.0),
            lat: 0.2 * s(2.9, 0.0),
        },
    }
}

fn fresh() -> FlightIdentifier<f32> {
    FlightIdentifier::flight(HoverConfig::default(), flight_sets()).unwrap()
}

fn learnt(from: u32, to: u32) -> FlightIdentifier<f32> {
    let mut id = fresh();
    for k in from..to {
        id.step(&sample(k)).unwrap();
    }
    id
}

fn bytes_of(id: &FlightIdentifier<f32>) -> Vec<u8> {
    let mut out = vec![0u8; FlightIdentifier::<f32>::SNAPSHOT_SIZE];
    assert_eq!(id.write_snapshot(KIND, &mut out), Ok(out.len()));
    out
}

/// A NOR flash in RAM: erase sets 0xFF, a write can only clear bits (AND), as real NOR.
struct RamFlash(Vec<u8>);

impl ErrorType for RamFlash {
    type Error = NorFlashErrorKind;
}
impl ReadNorFlash for RamFlash {
    const READ_SIZE: usize = 1;
    fn read(&mut self, offset: u32, bytes: &mut [u8]) -> Result<(), Self::Error> {
        let o = offset as usize;
        let src = self
            .0
            .get(o..o + bytes.len())
            .ok_or(NorFlashErrorKind::OutOfBounds)?;
        bytes.copy_from_slice(src);
        Ok(())
    }
    fn capacity(&self) -> usize {
        self.0.len()
    }
}
impl NorFlash for RamFlash {
    const WRITE_SIZE: usize = 4;
    const ERASE_SIZE: usize = 1024;
    fn erase(&mut self, from: u32, to: u32) -> Result<(), Self::Error> {
        assert!(
            from.is_multiple_of(1024) && to.is_multiple_of(1024),
            "erase aligned"
        );
        self.0[from as usize..to as usize].fill(0xFF);
        Ok(())
    }
    fn write(&mut self, offset: u32, bytes: &[u8]) -> Result<(), Self::Error> {
        assert!(
            offset.is_multiple_of(4) && bytes.len().is_multiple_of(4),
            "write aligned"
        );
        for (d, s) in self.0[offset as usize..].iter_mut().zip(bytes) {
            *d &= *s;
        }
        Ok(())
    }
}

const SLOTS: Slots = Slots {
    a: 0,
    b: 2048,
    size: 2048,
};

#[test]
fn snapshot_round_trip_and_layout() {
    let id = learnt(0, 200);
    let bytes = bytes_of(&id);
    assert_eq!(&bytes[..4], b"RIDX");
    assert_eq!(bytes[4..8], snapshot::VERSION.to_le_bytes());
    assert_eq!(bytes[8..12], KIND.to_le_bytes());
    let n = bytes.len();
    assert_eq!(
        bytes[n - 4..],
        snapshot::crc32(&bytes[..n - 4]).to_le_bytes()
    );
    let mut back = fresh();
    back.read_snapshot(KIND, &bytes).unwrap();
    assert_eq!(bytes_of(&back), bytes);
    // Short buffer: typed error.
    let mut short = vec![0u8; n - 1];
    assert!(matches!(
        id.write_snapshot(KIND, &mut short),
        Err(snapshot::WriteError::BufferTooShort { .. })
    ));
}

#[test]
fn refused_snapshot_changes_nothing() {
    let donor = bytes_of(&learnt(0, 200));
    let before = learnt(300, 400);
    let n = donor.len();
    // Every single-byte change of every 7th byte, a wrong kind, a wrong length.
    for at in (0..n).step_by(7) {
        let mut bad = donor.clone();
        bad[at] ^= 0x10;
        let mut id = before.clone();
        assert!(id.read_snapshot(KIND, &bad).is_err(), "byte {at}");
        assert_eq!(id, before);
    }
    let mut id = before.clone();
    assert_eq!(id.read_snapshot(KIND + 1, &donor), Err(Error::Incompatible));
    assert_eq!(
        id.read_snapshot(KIND, &donor[..n - 4]),
        Err(Error::Incompatible)
    );
    assert_eq!(id, before);
}

#[test]
fn records_alternate_and_the_newest_is_restored() {
    let mut flash = RamFlash(vec![0xFF; 4096]);
    let mut id = fresh();
    assert_eq!(
        record::read(&mut flash, &SLOTS, &mut id, KIND),
        Err(RecordError::NoValidRecord)
    );
    let mut saved = Vec::new();
    for s in 0..5u32 {
        let cur = learnt(0, 100 * (s + 1));
        let info = record::write(&mut flash, &SLOTS, &cur, KIND).unwrap();
        let slot = if s % 2 == 0 { Slot::A } else { Slot::B };
        assert_eq!(info, RecordInfo { slot, sequence: s });
        saved.push(bytes_of(&cur));
        let mut back = fresh();
        assert_eq!(record::read(&mut flash, &SLOTS, &mut back, KIND), Ok(info));
        assert_eq!(bytes_of(&back), *saved.last().unwrap());
    }
    // Tear the newest record (slot A, sequence 4) anywhere: the previous one (B, 3) is read.
    for at in (0..record::size_of::<FlightIdentifier<f32>>()).step_by(97) {
        let mut torn = RamFlash(flash.0.clone());
        torn.0[at] ^= 0x01;
        let mut back = fresh();
        let info = record::read(&mut torn, &SLOTS, &mut back, KIND).unwrap();
        assert_eq!(
            info,
            RecordInfo {
                slot: Slot::B,
                sequence: 3
            },
            "byte {at}"
        );
        assert_eq!(bytes_of(&back), saved[3]);
        // And the next write replaces the torn slot, not the intact one.
        let next = record::write(&mut torn, &SLOTS, &back, KIND).unwrap();
        assert_eq!(
            next,
            RecordInfo {
                slot: Slot::A,
                sequence: 4
            }
        );
    }
    // A half-written record (the rest still erased) is ignored too.
    let mut half = RamFlash(flash.0.clone());
    half.0[1000..2048].fill(0xFF);
    let mut back = fresh();
    assert_eq!(
        record::read(&mut half, &SLOTS, &mut back, KIND).map(|i| i.sequence),
        Ok(3)
    );
}

#[test]
fn sequence_numbers_wrap_around() {
    let id_old = learnt(0, 100);
    let id_new = learnt(0, 150);
    let size = record::size_of::<FlightIdentifier<f32>>();
    let (mut a, mut b) = (vec![0u8; size], vec![0u8; size]);
    record::encode(&id_old, KIND, u32::MAX, &mut a).unwrap();
    record::encode(&id_new, KIND, 0, &mut b).unwrap();
    let mut back = fresh();
    assert_eq!(
        record::decode(&mut back, KIND, &a, &b),
        Ok(RecordInfo {
            slot: Slot::B,
            sequence: 0
        })
    );
    assert_eq!(bytes_of(&back), bytes_of(&id_new));
    assert_eq!(
        record::plan(&a, &b),
        RecordInfo {
            slot: Slot::A,
            sequence: 1
        }
    );
    assert!(record::newer(0, u32::MAX) && !record::newer(u32::MAX, 0));
    assert!(record::newer(5, 4) && !record::newer(4, 4));
    assert_eq!(
        record::plan(&[], &[]),
        RecordInfo {
            slot: Slot::A,
            sequence: 0
        }
    );
}

#[test]
fn foreign_records_are_refused_and_nothing_is_imported() {
    let donor = learnt(0, 200);
    let size = record::size_of::<FlightIdentifier<f32>>();
    let mut rec = vec![0u8; size];
    record::encode(&donor, KIND, 7, &mut rec).unwrap();
    let before = learnt(300, 350);

    // Another kind.
    let mut id = before.clone();
    assert_eq!(
        record::decode(&mut id, KIND + 1, &rec, &[]),
        Err(RecordError::WrongKind {
            found: KIND,
            expected: KIND + 1
        })
    );
    assert_eq!(id, before);

    // Another configuration: a different sample period, and different premise sets.
    let config = HoverConfig {
        sample_period_us: 10_000,
        period_tolerance_us: 5_000,
        ..HoverConfig::default()
    };
    let mut other = FlightIdentifier::flight(config, flight_sets()).unwrap();
    let was = other.clone();
    assert!(matches!(
        record::decode(&mut other, KIND, &rec, &[]),
        Err(RecordError::WrongConfiguration { .. })
    ));
    assert_eq!(other, was);
    let sets = rotorid::hover::table3::three_sets((0.0, 2.0), (5.0, 2.5), (10.0, 2.5));
    let mut other = FlightIdentifier::flight(HoverConfig::default(), sets).unwrap();
    assert_ne!(other.config_hash(), before.config_hash());
    assert!(matches!(
        record::decode(&mut other, KIND, &rec, &[]),
        Err(RecordError::WrongConfiguration { .. })
    ));

    // Another record version (its CRC made valid again).
    let mut v2 = rec.clone();
    v2[4..8].copy_from_slice(&2u32.to_le_bytes());
    let n = v2.len();
    let crc = snapshot::crc32(&v2[..n - 4]).to_le_bytes();
    v2[n - 4..].copy_from_slice(&crc);
    let mut id = before.clone();
    assert_eq!(
        record::decode(&mut id, KIND, &v2, &[]),
        Err(RecordError::WrongVersion { found: 2 })
    );
    assert_eq!(id, before);

    // Another identifier type under the same kind code: the payload does not fit.
    let mut plain = PaperPlainIdentifier::<f32>::paper_plain(HoverConfig::default()).unwrap();
    let was = plain.clone();
    assert!(record::decode(&mut plain, KIND, &rec, &[]).is_err());
    assert_eq!(plain, was);

    // A value the import checks refuse, in an intact record (both CRCs made valid).
    let mut bad = rec.clone();
    let at = record::HEADER_SIZE + snapshot::HEADER_SIZE + 8; // θ₀ of the first estimator
    bad[at..at + 4].copy_from_slice(&f32::NAN.to_bits().to_le_bytes());
    let end = record::HEADER_SIZE + FlightIdentifier::<f32>::SNAPSHOT_SIZE;
    let crc = snapshot::crc32(&bad[record::HEADER_SIZE..end - 4]).to_le_bytes();
    bad[end - 4..end].copy_from_slice(&crc);
    let crc = snapshot::crc32(&bad[..n - 4]).to_le_bytes();
    bad[n - 4..].copy_from_slice(&crc);
    let mut id = before.clone();
    assert!(matches!(
        record::decode(&mut id, KIND, &bad, &[]),
        Err(RecordError::Refused(Error::NonFinite(_)))
    ));
    assert_eq!(id, before);

    // A valid-looking header whose payload length is garbage (near 2³²), CRC or not.
    for len in [u32::MAX - 3, u32::MAX - 27, 0x8000_0000, 4] {
        let mut g = rec.clone();
        g[20..24].copy_from_slice(&len.to_le_bytes());
        let mut id = before.clone();
        assert_eq!(
            record::decode(&mut id, KIND, &g, &[]),
            Err(RecordError::NoValidRecord)
        );
        assert_eq!(id, before);
    }

    // Erased slots.
    let mut id = before.clone();
    assert_eq!(
        record::decode(&mut id, KIND, &[0xFF; 2048], &[]),
        Err(RecordError::NoValidRecord)
    );
    assert_eq!(id, before);
}

#[test]
fn slots_that_do_not_fit_the_flash_are_refused() {
    let id = learnt(0, 10);
    let mut flash = RamFlash(vec![0xFF; 4096]);
    for slots in [
        Slots {
            a: 0,
            b: 1024,
            size: 2048,
        }, // overlap
        Slots {
            a: 0,
            b: 2048,
            size: 1024,
        }, // too small for a flight record
        Slots {
            a: 100,
            b: 2048,
            size: 2048,
        }, // not on a sector
        Slots {
            a: 0,
            b: 3072,
            size: 2048,
        }, // past the end
    ] {
        assert_eq!(
            record::write(&mut flash, &slots, &id, KIND),
            Err(RecordError::Layout),
            "{slots:?}"
        );
    }
    assert!(flash.0.iter().all(|&b| b == 0xFF), "nothing written");
}

#[test]
fn open_gives_the_snapshot_and_seal_frames_it() {
    let id = learnt(0, 120);
    let size = record::size_of::<FlightIdentifier<f32>>();
    let mut rec = vec![0u8; size];
    assert_eq!(record::encode(&id, KIND, 9, &mut rec), Ok(size));
    let (info, payload) = record::open(&rec, &[], KIND, id.config_hash()).unwrap();
    assert_eq!(
        info,
        RecordInfo {
            slot: Slot::A,
            sequence: 9
        }
    );
    assert_eq!(payload, &bytes_of(&id)[..]);
    // Framing the same snapshot by hand gives the same bytes.
    let mut framed = vec![0u8; size];
    framed[record::HEADER_SIZE..size - record::TRAILER_SIZE].copy_from_slice(payload);
    let n = record::seal(&mut framed, KIND, id.config_hash(), 9, payload.len());
    assert_eq!(n, Ok(size));
    assert_eq!(framed, rec);
    assert_eq!(
        record::seal(&mut framed[..size - 1], KIND, 0, 0, payload.len()),
        Err(RecordError::BufferTooShort {
            needed: size,
            got: size - 1
        })
    );
    assert!(matches!(
        record::open(&rec, &[], KIND, id.config_hash() ^ 1),
        Err(RecordError::WrongConfiguration { .. })
    ));
}
