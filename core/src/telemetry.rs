//! Telemetry codec (framing owned by the firmware work).
