//! Deterministic synthetic GU-DSL workspaces of any size, for benchmarks and stress tests.
