//! X-Cell 60 plant simulator.
