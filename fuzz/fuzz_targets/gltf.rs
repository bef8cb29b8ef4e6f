//! Fuzz target: the demo's gltf loader (see `loader_common.rs`).
#![no_main]

#[path = "loader_common.rs"]
mod loader_common;

libfuzzer_sys::fuzz_target!(|data: &[u8]| loader_common::run("gltf", data));
