//! A computation on its own thread, polled once a frame.

use crate::memo::Memo;
use eframe::egui;
use eframe::egui::mutex::Mutex;
use std::sync::{Arc, mpsc};
use std::time::Instant;

/// A computation running on a worker thread, started for `key`, with a
/// progress value of type `P` the worker updates and the panel reads. The
/// worker asks egui for a repaint when it reports and when it is done, so
/// the result is picked up ([`Job::poll`]) on the next frame. Dropping the
/// job abandons the result (the worker finishes and its answer is dropped).
pub(crate) struct Job<K, T, P = ()> {
    key: K,
    receiver: mpsc::Receiver<T>,
    progress: Arc<Mutex<P>>,
    started: Instant,
}

/// What a worker uses to report its progress.
pub(crate) struct Reporter<P> {
    slot: Arc<Mutex<P>>,
    ctx: egui::Context,
}

impl<P> Reporter<P> {
    /// Publishes `progress` and asks for a repaint to show it.
    pub fn report(&self, progress: P) {
        *self.slot.lock() = progress;
        self.ctx.request_repaint();
    }
}

/// What [`Job::poll`] found.
pub(crate) enum Poll<T> {
    /// Still running.
    Running,
    /// Done with this result.
    Done(T),
    /// The worker ended without a result (it panicked).
    Lost,
}

impl<K, T: Send + 'static, P: Send + 'static> Job<K, T, P> {
    /// Runs `work` on a thread named `name`; the error is one line.
    pub fn spawn(
        name: &str,
        key: K,
        initial: P,
        ctx: &egui::Context,
        work: impl FnOnce(&Reporter<P>) -> T + Send + 'static,
    ) -> Result<Self, String> {
        let (sender, receiver) = mpsc::channel();
        let progress = Arc::new(Mutex::new(initial));
        let reporter = Reporter {
            slot: progress.clone(),
            ctx: ctx.clone(),
        };
        std::thread::Builder::new()
            .name(format!("proxima-{name}"))
            .spawn(move || {
                let _ = sender.send(work(&reporter));
                reporter.ctx.request_repaint();
            })
            .map_err(|e| format!("cannot start the {name} job: {e}"))?;
        Ok(Self {
            key,
            receiver,
            progress,
            started: Instant::now(),
        })
    }
}

impl<K, T, P: Clone> Job<K, T, P> {
    /// The result, if the worker is done.
    pub fn poll(&self) -> Poll<T> {
        match self.receiver.try_recv() {
            Ok(result) => Poll::Done(result),
            Err(mpsc::TryRecvError::Empty) => Poll::Running,
            Err(mpsc::TryRecvError::Disconnected) => Poll::Lost,
        }
    }

    /// What the job was started for.
    pub fn key(&self) -> &K {
        &self.key
    }

    /// The latest progress reported.
    pub fn progress(&self) -> P {
        self.progress.lock().clone()
    }

    /// Seconds since the job started.
    pub fn seconds(&self) -> f32 {
        self.started.elapsed().as_secs_f32()
    }
}

/// A value computed on a worker thread and cached with the key it was
/// computed from. One job runs at a time: a key asked for while another is
/// being computed is started on a later frame, once that one is in.
pub(crate) struct Background<K, V> {
    /// The latest value in.
    pub memo: Memo<K, V>,
    job: Option<Job<K, V>>,
}

impl<K, V> Default for Background<K, V> {
    fn default() -> Self {
        Self {
            memo: Memo::default(),
            job: None,
        }
    }
}

impl<K: PartialEq + Clone + Send + 'static, V: Send + 'static> Background<K, V> {
    /// Starts `work(key)` on a thread named after `name`, unless the value of
    /// `key` is in or a job is running. The error is one line (no thread).
    pub fn request(
        &mut self,
        name: &str,
        key: K,
        ctx: &egui::Context,
        work: impl FnOnce(K) -> V + Send + 'static,
    ) -> Result<(), String> {
        if self.job.is_none() && !self.memo.holds(&key) {
            let argument = key.clone();
            self.job = Some(Job::spawn(name, key, (), ctx, move |_| work(argument))?);
        }
        Ok(())
    }

    /// Caches the running job's value if it is done; a lost job's value is
    /// `lost()` (`None`: nothing is cached and the key is asked again).
    pub fn poll(&mut self, lost: impl FnOnce() -> Option<V>) {
        let Some(job) = &self.job else {
            return;
        };
        let value = match job.poll() {
            Poll::Running => return,
            Poll::Done(value) => Some(value),
            Poll::Lost => lost(),
        };
        if let Some(value) = value {
            self.memo.set(job.key().clone(), value);
        }
        self.job = None;
    }

    /// `true` while a job runs.
    pub fn running(&self) -> bool {
        self.job.is_some()
    }
}

#[cfg(test)]
mod tests {
    use super::{Background, Job, Poll};
    use eframe::egui;

    fn wait<K, T, P: Clone>(job: &Job<K, T, P>) -> Poll<T> {
        for _ in 0..1000 {
            match job.poll() {
                Poll::Running => std::thread::sleep(std::time::Duration::from_millis(5)),
                other => return other,
            }
        }
        Poll::Running
    }

    #[test]
    fn a_job_delivers_its_result_progress_and_losses() {
        let ctx = egui::Context::default();
        let job = Job::spawn("test", 7, 0.0f32, &ctx, |reporter| {
            reporter.report(0.5);
            6 * 7
        })
        .unwrap();
        assert_eq!(*job.key(), 7);
        assert!(matches!(wait(&job), Poll::Done(42)));
        assert_eq!(job.progress(), 0.5);
        let lost: Job<(), u8> = Job::spawn("test", (), (), &ctx, |_| panic!("worker failure")).unwrap();
        assert!(matches!(wait(&lost), Poll::Lost));
    }

    #[test]
    fn a_background_value_is_computed_once_per_key() {
        let ctx = egui::Context::default();
        let settle = |squares: &mut Background<u32, u32>| {
            for _ in 0..1000 {
                squares.poll(|| None);
                if !squares.running() {
                    return;
                }
                std::thread::sleep(std::time::Duration::from_millis(5));
            }
        };
        let mut squares = Background::default();
        squares.request("test", 3, &ctx, |k| k * k).unwrap();
        assert!(squares.running());
        // Another key while the job runs starts nothing.
        squares.request("test", 4, &ctx, |_| unreachable!()).unwrap();
        settle(&mut squares);
        assert_eq!(squares.memo.get(&3), Some(&9));
        // The value of 3 is in: asking again starts nothing.
        squares.request("test", 3, &ctx, |_| unreachable!()).unwrap();
        assert!(!squares.running());
        squares.request("test", 4, &ctx, |k| k * k).unwrap();
        settle(&mut squares);
        assert_eq!((squares.memo.get(&4), squares.memo.get(&3)), (Some(&16), None));
    }
}
