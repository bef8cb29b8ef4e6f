//! Integration tests and benchmarks of the smoothtri workspace (no code of its own).
