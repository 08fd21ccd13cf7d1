//! Cross-crate integration tests live in `tests/tests/`; Python tests in `tests/python/`.
