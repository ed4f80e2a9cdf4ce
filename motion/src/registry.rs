//! How modules of one HAL instance find each other.
//!
//! LinuxCNC links `motmod` against whichever kinematics module was loaded
//! before it (the `kinematicsForward`/`kinematicsInverse` symbols resolve at
//! load time). Rust modules are compiled into the host, so the link is made
//! through a typed registry instead: a module that provides an interface
//! registers an `Arc` of it under the *instance name*, and a module that
//! needs it looks it up by the same name when it loads.
//!
//! Keying by instance keeps several instances in one process (tests run
//! side by side) apart. A registration lives exactly as long as the
//! [`Registration`] guard returned by [`InstanceRegistry::register`]; the
//! registering module stores that guard in state its component owns (its
//! safe-state hook), so the entry disappears when the component is unloaded
//! or the host shuts down, and a later `loadrt` can register again.
//!
//! The registry is only touched at load and unload time, never from a
//! realtime function: holders of the `Arc` call through it directly.

use std::sync::atomic::{AtomicU64, Ordering::Relaxed};
use std::sync::{Arc, Mutex, MutexGuard};

/// One registered provider.
struct Entry<T: ?Sized> {
    instance: String,
    owner: String,
    token: u64,
    value: Arc<T>,
}

/// A registry of providers of interface `T`, at most one per instance.
pub struct InstanceRegistry<T: ?Sized + Send + Sync + 'static> {
    /// What is registered, for messages ("kinematics").
    what: &'static str,
    entries: Mutex<Vec<Entry<T>>>,
    next_token: AtomicU64,
}

/// Returned when an instance already has a provider.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct AlreadyRegistered {
    /// What kind of provider ("kinematics").
    pub what: &'static str,
    /// The module that registered first.
    pub owner: String,
}

impl std::fmt::Display for AlreadyRegistered {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} already provided by '{}' in this instance",
            self.what, self.owner
        )
    }
}

impl<T: ?Sized + Send + Sync + 'static> InstanceRegistry<T> {
    /// An empty registry; `what` names the interface in messages.
    pub const fn new(what: &'static str) -> Self {
        InstanceRegistry {
            what,
            entries: Mutex::new(Vec::new()),
            next_token: AtomicU64::new(1),
        }
    }

    fn lock(&self) -> MutexGuard<'_, Vec<Entry<T>>> {
        self.entries.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// Registers `value`, provided by module `owner`, for `instance`. Fails
    /// if the instance already has a provider.
    pub fn register(
        &'static self,
        instance: &str,
        owner: &str,
        value: Arc<T>,
    ) -> Result<Registration<T>, AlreadyRegistered> {
        let mut entries = self.lock();
        if let Some(e) = entries.iter().find(|e| e.instance == instance) {
            return Err(AlreadyRegistered {
                what: self.what,
                owner: e.owner.clone(),
            });
        }
        let token = self.next_token.fetch_add(1, Relaxed);
        entries.push(Entry {
            instance: instance.to_string(),
            owner: owner.to_string(),
            token,
            value,
        });
        Ok(Registration {
            registry: self,
            token,
        })
    }

    /// The provider registered for `instance`, with the name of its module.
    pub fn get(&self, instance: &str) -> Option<(String, Arc<T>)> {
        self.lock()
            .iter()
            .find(|e| e.instance == instance)
            .map(|e| (e.owner.clone(), e.value.clone()))
    }

    fn remove(&self, token: u64) {
        self.lock().retain(|e| e.token != token);
    }
}

/// Keeps a registration alive; dropping it removes the entry.
pub struct Registration<T: ?Sized + Send + Sync + 'static> {
    registry: &'static InstanceRegistry<T>,
    token: u64,
}

impl<T: ?Sized + Send + Sync + 'static> Drop for Registration<T> {
    fn drop(&mut self) {
        self.registry.remove(self.token);
    }
}

impl<T: ?Sized + Send + Sync + 'static> std::fmt::Debug for Registration<T> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Registration")
            .field("what", &self.registry.what)
            .field("token", &self.token)
            .finish()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    static REG: InstanceRegistry<dyn Fn() -> i32 + Send + Sync> = InstanceRegistry::new("thing");

    #[test]
    fn one_provider_per_instance_for_as_long_as_the_guard_lives() {
        let a = REG
            .register("reg-a", "mod1", Arc::new(|| 1))
            .expect("first registration");
        let err = REG.register("reg-a", "mod2", Arc::new(|| 2)).unwrap_err();
        assert_eq!(err.owner, "mod1");
        assert!(err.to_string().contains("thing already provided by 'mod1'"));
        // Another instance is independent.
        let b = REG.register("reg-b", "mod2", Arc::new(|| 2)).unwrap();
        let (owner, f) = REG.get("reg-a").unwrap();
        assert_eq!((owner.as_str(), f()), ("mod1", 1));
        assert_eq!(REG.get("reg-b").unwrap().1(), 2);
        drop(a);
        assert!(REG.get("reg-a").is_none());
        let _a2 = REG.register("reg-a", "mod3", Arc::new(|| 3)).unwrap();
        assert_eq!(REG.get("reg-a").unwrap().1(), 3);
        drop(b);
        assert!(REG.get("reg-b").is_none());
    }
}
