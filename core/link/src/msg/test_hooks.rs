//! Test hooks of the example firmware: cost measurement, fault injection, memory report.
//!
//! These messages exist so that the example firmware (`firmware-example/`) and the test suite
//! (`host-tests/`) can measure and break a firmware on purpose; they are not protocol every
//! user of the link needs, and a flight firmware may answer them with `Nack` (`UnknownType`).
//! `FaultInject` carries one [`FaultKind`] byte and `MemoryRequest` is empty, so they have no
//! struct here.

wire_enum! {
    /// Dummy workloads the `CostRequest` can run (byte 0 of its payload).
    #[non_exhaustive]
    #[derive(Clone, Copy, Debug, PartialEq, Eq)]
    #[cfg_attr(feature = "defmt", derive(defmt::Format))]
    pub enum Workload {
        /// Nothing: measures the stopwatch overhead.
        Empty = 0,
        /// `iterations` rounds of a 32-bit xorshift (integer ALU).
        Xorshift = 1,
        /// `iterations` single-precision multiply-adds (FPU).
        FloatMac = 2,
        /// [`encode_frame`](crate::encode_frame) of a 240-byte payload (CRC-32 + COBS),
        /// `iterations` times.
        EncodeFrame = 3,
    }
}

fixed_payload! {
    /// `CostRequest` payload (5 B): workload u8, iterations u32.
    #[derive(Clone, Copy, Debug, PartialEq, Eq)]
    #[cfg_attr(feature = "defmt", derive(defmt::Format))]
    pub struct CostRequest for [CostRequest] {
        /// What to run.
        pub workload: Workload,
        /// How many rounds.
        pub iterations: u32,
    }
}

fixed_payload! {
    /// `Cost` payload (17 B): workload u8, iterations u32, ticks u64, result u32.
    #[derive(Clone, Copy, Debug, PartialEq, Eq)]
    #[cfg_attr(feature = "defmt", derive(defmt::Format))]
    pub struct CostReport for [Cost] {
        /// The workload that ran.
        pub workload: Workload,
        /// Rounds that ran.
        pub iterations: u32,
        /// Elapsed SysTick ticks (core clock; under QEMU `-icount shift=0` one tick is 40
        /// executed instructions), stopwatch overhead included.
        pub ticks: u64,
        /// Result of the workload (keeps the optimiser from deleting it; deterministic).
        pub result: u32,
    }
}

wire_enum! {
    /// What the `FaultInject` test hook does (byte 0 of its payload).
    #[non_exhaustive]
    #[derive(Clone, Copy, Debug, PartialEq, Eq)]
    #[cfg_attr(feature = "defmt", derive(defmt::Format))]
    pub enum FaultKind {
        /// Rust `panic!`.
        Panic = 0,
        /// Undefined instruction: UsageFault escalated to HardFault.
        HardFault = 1,
    }
}

fixed_payload! {
    /// `Memory` payload (16 B): RAM the firmware uses, in bytes — stack region size, stack
    /// peak (high-water mark of the painted stack), static data (`.data` + `.bss` +
    /// `.uninit`), and the RAM region size.
    #[derive(Clone, Copy, Debug, PartialEq, Eq)]
    #[cfg_attr(feature = "defmt", derive(defmt::Format))]
    pub struct MemoryReport for [Memory] {
        /// Bytes between the end of static data and the initial stack pointer.
        pub stack_size: u32,
        /// Deepest stack use since boot (bytes below the initial stack pointer).
        pub stack_peak: u32,
        /// Static RAM, in bytes.
        pub static_ram: u32,
        /// RAM region, in bytes.
        pub ram_size: u32,
    }
}

#[cfg(test)]
mod tests {
    use super::super::message::testing::{rejects_truncated_and_extended, roundtrip};
    use super::super::message::Payload;
    use super::*;

    #[test]
    fn hooks_roundtrip() {
        let c = CostReport {
            workload: Workload::FloatMac,
            iterations: 1000,
            ticks: 1 << 40,
            result: 7,
        };
        let b = roundtrip(&c);
        assert_eq!(b.len(), 17);
        assert_eq!(b[5..13], (1u64 << 40).to_le_bytes());
        assert_eq!(CostReport::read(&b), Ok(c));
        rejects_truncated_and_extended::<CostReport>(&b);
        assert!(CostRequest::read(&[9, 0, 0, 0, 0]).is_err());
        assert!(CostRequest::read(&[1, 0, 0, 0]).is_err());
        assert!(CostRequest::read(&[1, 0, 0, 0, 0, 0]).is_err());
        assert_eq!(
            CostRequest::read(&[2, 1, 0, 0, 0]),
            Ok(CostRequest {
                workload: Workload::FloatMac,
                iterations: 1
            })
        );
        let m = MemoryReport {
            stack_size: 1,
            stack_peak: 2,
            static_ram: 3,
            ram_size: 4,
        };
        let b = roundtrip(&m);
        assert_eq!(b, [1, 0, 0, 0, 2, 0, 0, 0, 3, 0, 0, 0, 4, 0, 0, 0]);
        assert_eq!(MemoryReport::read(&b), Ok(m));
        rejects_truncated_and_extended::<MemoryReport>(&b);
        assert_eq!(FaultKind::from_u8(1), Some(FaultKind::HardFault));
        assert_eq!(FaultKind::from_u8(2), None);
    }
}
