//! FMI
