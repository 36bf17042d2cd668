//! Prints the memory each identifier needs (`size_of`, bytes), f32 and f64.
//!
//! Run: `cargo run -p rotorid --example memory`
use core::mem::size_of;
use rotorid::{
    ExtendedFuzzyIdentifier, ExtendedPlainIdentifier, PaperFuzzyIdentifier, PaperPlainIdentifier,
};

fn main() {
    println!("| identifier | f32 (bytes) | f64 (bytes) |");
    println!("|---|---|---|");
    println!(
        "| PaperFuzzyIdentifier | {} | {} |",
        size_of::<PaperFuzzyIdentifier<f32>>(),
        size_of::<PaperFuzzyIdentifier<f64>>()
    );
    println!(
        "| PaperPlainIdentifier | {} | {} |",
        size_of::<PaperPlainIdentifier<f32>>(),
        size_of::<PaperPlainIdentifier<f64>>()
    );
    println!(
        "| ExtendedFuzzyIdentifier | {} | {} |",
        size_of::<ExtendedFuzzyIdentifier<f32>>(),
        size_of::<ExtendedFuzzyIdentifier<f64>>()
    );
    println!(
        "| ExtendedPlainIdentifier | {} | {} |",
        size_of::<ExtendedPlainIdentifier<f32>>(),
        size_of::<ExtendedPlainIdentifier<f64>>()
    );
}
