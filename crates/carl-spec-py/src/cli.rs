//! The Python package's `carl-spec` command: the carl-spec crate's command line, run in this
//! process (`python/carl_spec/_cli.py` calls it from the console script pip installs).

use std::ffi::OsString;

use pyo3::prelude::*;

/// Run the command line `argv` (program name first) and return its exit code. The GIL is
/// released while it runs.
#[pyfunction]
pub(crate) fn cli_main(py: Python<'_>, argv: Vec<OsString>) -> u8 {
    py.detach(|| carl_spec::cli::run(argv))
}
