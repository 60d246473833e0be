//! Pieces of work done on every core and handed, in order, to the thread
//! that asked for them: a file's chunks of targets corrected by the
//! workers while the calling thread writes the ones before.
//!
//! The correction once went a batch of chunks at a time (each batch
//! corrected on every core while the batch before was written): every
//! core waited at each batch's end for the slowest chunk, and the thread
//! that asked stood idle. Here each worker takes the next chunk as it is
//! free, at most [`in_order`]'s window ahead of the writing, so memory
//! holds a few chunks however long the file.

use std::collections::BTreeMap;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{mpsc, Condvar, Mutex, MutexGuard};

/// `work(k)` for `k` in `0..n`, on `workers` threads, each piece at most
/// `window` pieces ahead of the last one handed over; `put(k, piece)` on
/// the calling thread for `k = 0, 1, ...` in order. The first error `put`
/// gives stops the workers (those under way finish their piece) and is
/// returned.
pub(super) fn in_order<T: Send, E>(
    n: usize,
    workers: usize,
    window: usize,
    work: impl Fn(usize) -> T + Sync,
    mut put: impl FnMut(usize, T) -> Result<(), E>,
) -> Result<(), E> {
    let window = window.max(1);
    let next = AtomicUsize::new(0);
    let stop = AtomicBool::new(false);
    // How many pieces were handed over, for the workers to wait on.
    let handed = (Mutex::new(0usize), Condvar::new());
    std::thread::scope(|s| {
        let (tx, rx) = mpsc::channel::<(usize, T)>();
        for _ in 0..workers.clamp(1, n.max(1)) {
            let tx = tx.clone();
            let (next, stop, handed, work) = (&next, &stop, &handed, &work);
            s.spawn(move || loop {
                let k = next.fetch_add(1, Ordering::Relaxed);
                if k >= n {
                    break;
                }
                {
                    let mut done = lock(&handed.0);
                    while k >= *done + window && !stop.load(Ordering::Relaxed) {
                        done = handed.1.wait(done).unwrap_or_else(|e| e.into_inner());
                    }
                }
                if stop.load(Ordering::Relaxed) {
                    break;
                }
                if tx.send((k, work(k))).is_err() {
                    break;
                }
            });
        }
        drop(tx);
        let mut held: BTreeMap<usize, T> = BTreeMap::new();
        let mut expect = 0;
        let mut result = Ok(());
        'received: for (k, piece) in rx.iter() {
            held.insert(k, piece);
            while let Some(piece) = held.remove(&expect) {
                result = put(expect, piece);
                expect += 1;
                // Set before the count moves: no worker the count lets
                // through starts another piece.
                stop.store(result.is_err(), Ordering::Relaxed);
                *lock(&handed.0) = expect;
                handed.1.notify_all();
                if result.is_err() {
                    break 'received;
                }
            }
        }
        result
    })
}

/// The count, whether or not a worker panicked holding it (a panic
/// leaves nothing this count relies on half done).
fn lock(m: &Mutex<usize>) -> MutexGuard<'_, usize> {
    m.lock().unwrap_or_else(|e| e.into_inner())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pieces_are_handed_over_in_order_within_the_window() {
        let ahead = AtomicUsize::new(0);
        let handed = AtomicUsize::new(0);
        let mut seen = Vec::new();
        let r: Result<(), ()> = in_order(
            1000,
            3,
            4,
            |k| {
                // No piece starts more than the window ahead of the writing.
                let h = handed.load(Ordering::SeqCst);
                ahead.fetch_max(k.saturating_sub(h), Ordering::SeqCst);
                k * 2
            },
            |k, v| {
                assert_eq!(v, k * 2);
                seen.push(k);
                handed.store(k + 1, Ordering::SeqCst);
                Ok(())
            },
        );
        assert!(r.is_ok());
        assert_eq!(seen, (0..1000).collect::<Vec<_>>());
        assert!(ahead.load(Ordering::SeqCst) < 4, "{ahead:?}");
    }

    #[test]
    fn the_first_error_stops_the_work() {
        let started = AtomicUsize::new(0);
        let r = in_order(
            100_000,
            2,
            8,
            |k| {
                started.fetch_add(1, Ordering::SeqCst);
                k
            },
            |k, _| if k == 10 { Err(k) } else { Ok(()) },
        );
        assert_eq!(r, Err(10));
        // The workers stopped within the window of the failing piece.
        assert!(started.load(Ordering::SeqCst) <= 10 + 8 + 2, "{started:?}");
    }

    #[test]
    fn nothing_to_do_is_done() {
        let r: Result<(), ()> = in_order(0, 2, 4, |k| k, |_, _| Err(()));
        assert!(r.is_ok());
    }
}
