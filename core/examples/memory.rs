//! Prints the memory each identifier needs (`size_of`, bytes), f32 and f64, and that of the
//! one-step observer and of the search for its gain (ten candidates) that run beside one.
//!
//! Run: `cargo run -p rotorid --example memory`
use core::mem::size_of;
use rotorid::hover::{GainSearch, Observer};
use rotorid::{
    ExtendedFuzzyIdentifier, ExtendedLocalIdentifier, ExtendedPlainIdentifier, FlightIdentifier,
    FlightPlainIdentifier, PaperFuzzyIdentifier, PaperLocalIdentifier, PaperPlainIdentifier,
};

macro_rules! row {
    ($t:ident) => {
        println!(
            "| {} | {} | {} |",
            stringify!($t),
            size_of::<$t<f32>>(),
            size_of::<$t<f64>>()
        );
    };
}

fn main() {
    println!("| identifier | f32 (bytes) | f64 (bytes) |");
    println!("|---|---|---|");
    row!(FlightIdentifier);
    row!(FlightPlainIdentifier);
    row!(PaperFuzzyIdentifier);
    row!(PaperLocalIdentifier);
    row!(PaperPlainIdentifier);
    row!(ExtendedFuzzyIdentifier);
    row!(ExtendedLocalIdentifier);
    row!(ExtendedPlainIdentifier);
    row!(Observer);
    println!(
        "| GainSearch<_, 10> | {} | {} |",
        size_of::<GainSearch<f32, 10>>(),
        size_of::<GainSearch<f64, 10>>()
    );
}
