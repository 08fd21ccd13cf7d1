//! The FMI layer. Not built yet: see issue "FMUs".
