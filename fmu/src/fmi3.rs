//! FMI 3.0 co-simulation ABI (built next).
