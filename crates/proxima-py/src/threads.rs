//! The `threads=` argument of batch calls: rayon pools of a given size,
//! made once per size and calling thread, and kept.

use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use rayon::ThreadPool;
use std::cell::RefCell;
use std::collections::HashMap;
use std::sync::Arc;

/// The pool of `threads` workers, or `None` for rayon's global pool (all
/// cores) when `threads` is `None`. Fails with a `ValueError` for 0 or more
/// than [`proxima::budget::max_threads`] (the command line's cap).
///
/// Each calling (Python) thread has its own pools: `threads=k` means k
/// workers for this call, so two Python threads that each ask for one run
/// side by side instead of queueing on one shared worker.
pub fn pool(threads: Option<i64>) -> PyResult<Option<Arc<ThreadPool>>> {
    let Some(threads) = threads else {
        return Ok(None);
    };
    let cap = proxima::budget::max_threads();
    let Some(threads) = usize::try_from(threads).ok().filter(|&t| (1..=cap).contains(&t)) else {
        return Err(PyValueError::new_err(format!(
            "threads: {threads} is not between 1 and {cap} (4 per core on this machine, at least 8), or None for all cores"
        )));
    };
    thread_local! {
        static POOLS: RefCell<HashMap<usize, Arc<ThreadPool>>> = RefCell::default();
    }
    POOLS.with_borrow_mut(|pools| {
        if let Some(pool) = pools.get(&threads) {
            return Ok(Some(pool.clone()));
        }
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .thread_name(|i| format!("proxima-{i}"))
            .build()
            .map_err(|e| PyValueError::new_err(format!("threads: {threads}: {e}")))?;
        let pool = Arc::new(pool);
        pools.insert(threads, pool.clone());
        Ok(Some(pool))
    })
}

/// Runs `work` without the GIL (other Python threads go on meanwhile) on
/// the pool that `threads` names.
pub fn run<T: Send>(py: Python<'_>, threads: Option<i64>, work: impl FnOnce() -> T + Send) -> PyResult<T> {
    let pool = pool(threads)?;
    Ok(py.detach(|| match pool {
        Some(pool) => pool.install(work),
        None => work(),
    }))
}
