//! Worker threads do not survive `fork`: a guard that refuses, with the
//! remedy, what would otherwise hang in a forked child.

use pyo3::exceptions::PyRuntimeError;
use pyo3::PyResult;
use std::sync::atomic::{AtomicU32, Ordering};

/// The process that first ran parallel work (rayon's thread pool); 0: none yet.
static POOL_OWNER: AtomicU32 = AtomicU32::new(0);

/// Ok in the process whose threads run the parallel work; an error naming
/// the remedy in a process forked from it after that work began (rayon's
/// pool, created in the parent, has no threads in the child: every parallel
/// call there would wait forever).
pub(crate) fn parallel_guard() -> PyResult<()> {
    let pid = std::process::id();
    match POOL_OWNER.compare_exchange(0, pid, Ordering::SeqCst, Ordering::SeqCst) {
        Ok(_) => Ok(()),
        Err(owner) if owner == pid => Ok(()),
        Err(owner) => Err(PyRuntimeError::new_err(format!(
            "mcrt_noise ran parallel work in process {owner} before it forked this process ({pid}); its worker \
             threads do not survive fork, so this call would hang. Start worker processes with \
             multiprocessing.get_context(\"spawn\") (or \"forkserver\"), or call mcrt_noise only after forking"
        ))),
    }
}
