//! A structure built on first use, once, even when several threads
//! ask for it at the same time.

use std::sync::{Mutex, OnceLock, PoisonError};

/// A value built by the first caller of [`get_or_try_init`](Self::get_or_try_init)
/// that succeeds; later callers get the same value without waiting. Callers
/// that arrive while it is being built wait for that build instead of
/// starting their own (building a tree twice would waste seconds and memory).
pub struct Lazy<T> {
    value: OnceLock<T>,
    building: Mutex<()>,
}

impl<T> Default for Lazy<T> {
    fn default() -> Self {
        Self {
            value: OnceLock::new(),
            building: Mutex::new(()),
        }
    }
}

impl<T> Lazy<T> {
    /// The value, built by `build` if no earlier call built it. A failed
    /// build leaves nothing behind: the next call tries again.
    pub fn get_or_try_init<E>(&self, build: impl FnOnce() -> Result<T, E>) -> Result<&T, E> {
        if let Some(value) = self.value.get() {
            return Ok(value);
        }
        let _building = self.building.lock().unwrap_or_else(PoisonError::into_inner);
        if let Some(value) = self.value.get() {
            return Ok(value);
        }
        let value = build()?;
        Ok(self.value.get_or_init(|| value))
    }

    /// The value, if it has been built.
    pub fn get(&self) -> Option<&T> {
        self.value.get()
    }

    /// The value, if it has been built, to change it (no other caller can
    /// be building it: the borrow is exclusive).
    pub fn get_mut(&mut self) -> Option<&mut T> {
        self.value.get_mut()
    }

    /// Takes the value out, leaving nothing built.
    pub fn take(&mut self) -> Option<T> {
        self.value.take()
    }

    /// Puts `value` in, replacing what was built.
    pub fn put(&mut self, value: T) {
        self.value = OnceLock::from(value);
    }
}
