//! Peak resident memory of this process and of each rank of a distributed run: the high-water
//! mark `VmHWM` of `/proc/self/status` (Linux), the most physical memory the process held at
//! once. A run's memory is what stops a user who outgrows one machine, so the scene command and
//! the `mpirun` variants of the catalogue report it per rank.

use impact_solver::distributed::Communicator;

/// Keeps glibc's mmap threshold at 128 KiB for the whole run, so that every large array
/// (a nodal field, an element array, a mesh) has a mapping of its own and goes back to the
/// system when freed. By default glibc raises the threshold to the size of each mapped block
/// freed (up to 32 MiB, `mallopt(3)`, `M_MMAP_THRESHOLD`): once a rank has freed the whole
/// mesh it read (16 MB of connectivity for a million elements), the arrays it allocates next
/// come from the heap instead, and what is freed between them stays resident. Measured on
/// the 1 M-element elastic block (`docs/scale.md`): the peak per rank falls by 5-7 MiB on two
/// ranks and about 5 MiB on four, one process's by 0.5-1 MiB, with the same step time. Call it
/// first in `main`, before any thread exists. Does nothing where the C library is not glibc.
pub fn keep_large_blocks_mapped() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    {
        /// The size from which glibc maps each block on its own (bytes): its default
        /// starting value, 128 KiB.
        const MMAP_THRESHOLD: i32 = 128 * 1024;
        // SAFETY: `mallopt` only sets an allocator parameter; called before any other thread
        // exists, it races with no allocation. Its status (1 set, 0 refused) changes nothing:
        // a refused setting leaves glibc's default, which is still correct, only larger.
        let _set = unsafe { libc::mallopt(libc::M_MMAP_THRESHOLD, MMAP_THRESHOLD) };
    }
}

/// This process's peak resident memory in bytes (`VmHWM`), or `None` where `/proc` does not
/// give it (not Linux, or a kernel without the field).
pub fn peak_resident_bytes() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    parse_vm_hwm(&status)
}

/// The `VmHWM` line of a `/proc/<pid>/status` text in bytes (the kernel writes it in kB, 1024
/// bytes: `proc(5)`).
fn parse_vm_hwm(status: &str) -> Option<u64> {
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let mut words = line["VmHWM:".len()..].split_whitespace();
    let kib: u64 = words.next()?.parse().ok()?;
    (words.next() == Some("kB")).then_some(kib * 1024)
}

/// Every rank's peak resident memory in MiB, in rank order (this process alone without
/// `ranks`); a rank that cannot read it gives `NaN`. Collective: every rank calls it.
pub fn peak_resident_mib_per_rank(ranks: Option<&dyn Communicator>) -> Vec<f64> {
    let mine = peak_resident_bytes().map_or(f64::NAN, |b| b as f64 / (1024.0 * 1024.0));
    match ranks {
        None => vec![mine],
        Some(c) => {
            let mut all = vec![0.0; c.size()];
            c.all_gather_f64(&[mine], &vec![1; c.size()], &mut all);
            all
        }
    }
}

/// The report's line: `peak resident memory (VmHWM): 812.3 MiB`, or per rank
/// `... per rank: 412.1, 405.0 MiB`.
pub fn peak_memory_line(per_rank: &[f64]) -> String {
    let values: Vec<String> = per_rank.iter().map(|m| format!("{m:.1}")).collect();
    if per_rank.len() == 1 {
        format!("peak resident memory (VmHWM): {} MiB", values[0])
    } else {
        format!(
            "peak resident memory (VmHWM) per rank: {} MiB",
            values.join(", ")
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use impact_solver::distributed::ThreadGroup;

    #[test]
    fn the_high_water_mark_is_read_in_kilobytes() {
        let status =
            "Name:\timpact-vv\nVmPeak:\t  900000 kB\nVmHWM:\t   12345 kB\nVmRSS:\t 100 kB\n";
        assert_eq!(parse_vm_hwm(status), Some(12345 * 1024));
        assert_eq!(parse_vm_hwm("VmRSS:\t 100 kB\n"), None);
        assert_eq!(parse_vm_hwm("VmHWM:\t 100 MB\n"), None);
    }

    #[cfg(target_os = "linux")]
    #[test]
    fn this_process_has_held_at_least_what_it_holds_now() {
        // 64 MiB touched page by page must show in the high-water mark.
        let block = vec![1u8; 64 << 20];
        let peak = peak_resident_bytes().expect("Linux gives VmHWM");
        assert!(peak >= block.len() as u64, "{peak} bytes");
        assert_eq!(
            block.iter().map(|&b| b as usize).sum::<usize>(),
            block.len()
        );
    }

    #[test]
    fn every_rank_gets_every_ranks_value() {
        let group = ThreadGroup::new(3);
        let got: Vec<Vec<f64>> = std::thread::scope(|s| {
            let handles: Vec<_> = group
                .iter()
                .map(|c| s.spawn(move || peak_resident_mib_per_rank(Some(c as &dyn Communicator))))
                .collect();
            handles.into_iter().map(|h| h.join().unwrap()).collect()
        });
        // Ranks as threads share one process, so one high-water mark read three times.
        for values in &got {
            assert_eq!(values.len(), 3);
            assert!(values.iter().all(|m| *m > 0.0), "{values:?}");
        }
        assert!(peak_memory_line(&got[0]).contains("per rank"));
        assert!(peak_memory_line(&got[0][..1]).ends_with(" MiB"));
    }
}
