//! Integration tests and benchmarks of the smoothtri workspace. The README is included here so
//! its embedding example is compiled and run as a doctest by `cargo test --workspace`.
#![doc = include_str!("../README.md")]
