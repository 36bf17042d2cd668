//! Host-side (std) companion of the `rotorid` core: plant simulator, experiments, log format,
//! independent reference implementation and the firmware link driver.
pub mod firmware_link;
pub mod plant;
pub mod reference;
