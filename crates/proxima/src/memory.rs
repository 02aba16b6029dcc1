//! Large arrays on transparent huge pages.
//!
//! Contract: [`HugePageArray`] is an immutable array of plain-old-data values
//! that reads as a slice. When it holds at least 8 MiB (on Linux) it lives in
//! its own anonymous mapping, aligned to 2 MiB and advised `MADV_HUGEPAGE`;
//! elsewhere (small arrays, other systems, a refused mapping) it is an
//! ordinary `Vec`. Which of the two never changes what it reads back. No code
//! of ours is `unsafe`: the mapping comes from `memmap2`, the typed view from
//! `bytemuck`.
//!
//! ```
//! use proxima::memory::HugePageArray;
//! let array = HugePageArray::new(vec![1u32, 2, 3]);
//! assert_eq!(&array[..], &[1, 2, 3]);
//! assert!(!array.is_mapped()); // small arrays stay in a `Vec`
//! ```
//!
//! Why: a closest-point query on a big mesh is bound by memory latency, its
//! nodes and triangles spread over tens of megabytes, far more than the TLB
//! covers with 4 KiB pages; a `Vec` from the allocator never asks for huge
//! pages (Linux's usual `madvise` mode).
//!
//! The advice comes once the array is written, not before: advised first,
//! each first write to a 2 MiB page waits for the kernel to find and zero a
//! huge page, which on virtual machines that return free memory to their host
//! made builds much slower; advised afterwards, the kernel's `khugepaged`
//! moves the arrays to huge pages in the background and no build waits
//! (measurements in `docs/perf-log.md`, "Huge pages").

use bytemuck::Pod;
use std::fmt;
use std::ops::Deref;

/// Size of a transparent huge page on x86-64 and most aarch64 kernels.
pub const HUGE_PAGE: usize = 2 << 20;

/// Arrays smaller than this stay in a `Vec`: one huge page could not hold
/// more than a few of them, and small arrays stay in cache anyway.
const MAPPED_FROM: usize = 4 * HUGE_PAGE;

/// An immutable array of `T`, on transparent huge pages when large (see the
/// module documentation). Dereferences to `&[T]`.
pub struct HugePageArray<T: Pod> {
    storage: Storage<T>,
}

enum Storage<T> {
    Heap(Vec<T>),
    #[cfg(target_os = "linux")]
    Mapped {
        map: memmap2::MmapMut,
        /// Byte offset of the first element: the first 2 MiB boundary in the map.
        offset: usize,
        len: usize,
    },
}

impl<T: Pod> HugePageArray<T> {
    /// The values of `values`, moved to huge pages when they take at least
    /// 8 MiB.
    pub fn new(values: Vec<T>) -> Self {
        #[cfg(target_os = "linux")]
        if std::mem::size_of_val(&values[..]) >= MAPPED_FROM
            && let Some(storage) = Self::mapped(&values)
        {
            return Self { storage };
        }
        Self {
            storage: Storage::Heap(values),
        }
    }

    /// A copy of `values` in a fresh anonymous mapping advised
    /// `MADV_HUGEPAGE`, or `None` if the system refuses either step.
    #[cfg(target_os = "linux")]
    fn mapped(values: &[T]) -> Option<Storage<T>> {
        let bytes = std::mem::size_of_val(values);
        // One huge page more than needed, so that the data can start on a
        // 2 MiB boundary: only whole, aligned 2 MiB ranges become huge pages.
        let mut map = memmap2::MmapMut::map_anon(bytes + HUGE_PAGE).ok()?;
        let start = map.as_ptr() as usize;
        let offset = start.next_multiple_of(HUGE_PAGE) - start;
        map[offset..offset + bytes].copy_from_slice(bytemuck::cast_slice(values));
        map.advise(memmap2::Advice::HugePage).ok()?;
        Some(Storage::Mapped {
            map,
            offset,
            len: values.len(),
        })
    }

    /// The values, to change in place (a refit rewrites a tree's boxes
    /// where they lie).
    pub(crate) fn as_mut_slice(&mut self) -> &mut [T] {
        self.storage.as_mut_slice()
    }

    /// `true` when the values live in a mapping advised for huge pages
    /// (whether the kernel granted them is its own decision; see
    /// [`huge_page_bytes`]).
    pub fn is_mapped(&self) -> bool {
        !matches!(self.storage, Storage::Heap(_))
    }
}

/// A [`HugePageArray`] filled in place, element by element: for arrays whose
/// final size is known (or bounded) in advance, this avoids building a `Vec`
/// first and copying it, which on a large tree costs as much again as the
/// filling itself (page faults on both copies).
pub(crate) struct HugePageVec<T: Pod> {
    storage: Storage<T>,
    /// Elements the mapping holds (unused for a `Vec`).
    capacity: usize,
}

impl<T: Pod> HugePageVec<T> {
    /// Room for `capacity` elements, mapped on huge pages when that is at
    /// least 8 MiB. Untouched capacity costs address space only.
    pub(crate) fn with_capacity(capacity: usize) -> Self {
        #[cfg(target_os = "linux")]
        if capacity.saturating_mul(std::mem::size_of::<T>()) >= MAPPED_FROM
            && let Some((map, offset)) = Self::map(capacity)
        {
            return Self {
                storage: Storage::Mapped { map, offset, len: 0 },
                capacity,
            };
        }
        Self {
            storage: Storage::Heap(Vec::with_capacity(capacity)),
            capacity,
        }
    }

    /// An anonymous mapping for `capacity` elements advised `MADV_HUGEPAGE`,
    /// and the offset of its first 2 MiB boundary.
    #[cfg(target_os = "linux")]
    fn map(capacity: usize) -> Option<(memmap2::MmapMut, usize)> {
        let bytes = capacity.checked_mul(std::mem::size_of::<T>())?;
        let map = memmap2::MmapMut::map_anon(bytes.checked_add(HUGE_PAGE)?).ok()?;
        let start = map.as_ptr() as usize;
        Some((map, start.next_multiple_of(HUGE_PAGE) - start))
    }

    /// Number of elements.
    pub(crate) fn len(&self) -> usize {
        match &self.storage {
            Storage::Heap(values) => values.len(),
            #[cfg(target_os = "linux")]
            Storage::Mapped { len, .. } => *len,
        }
    }

    /// Appends `value`. Past the capacity of a mapping, the elements move to
    /// a `Vec` (correct, just without huge pages).
    pub(crate) fn push(&mut self, value: T) {
        #[cfg(target_os = "linux")]
        if let Storage::Mapped { map, offset, len } = &mut self.storage {
            if *len < self.capacity {
                let size = std::mem::size_of::<T>();
                let at = *offset + *len * size;
                map[at..at + size].copy_from_slice(bytemuck::bytes_of(&value));
                *len += 1;
                return;
            }
            let mut values = self.as_mut_slice().to_vec();
            values.push(value);
            self.storage = Storage::Heap(values);
            return;
        }
        if let Storage::Heap(values) = &mut self.storage {
            values.push(value);
        }
    }

    /// The elements, to change in place.
    pub(crate) fn as_mut_slice(&mut self) -> &mut [T] {
        self.storage.as_mut_slice()
    }

    /// The finished array, without a copy.
    pub(crate) fn finish(self) -> HugePageArray<T> {
        #[cfg(target_os = "linux")]
        if let Storage::Mapped { map, .. } = &self.storage {
            let _ = map.advise(memmap2::Advice::HugePage);
        }
        HugePageArray { storage: self.storage }
    }
}

impl<T: Pod> Storage<T> {
    fn as_mut_slice(&mut self) -> &mut [T] {
        match self {
            Storage::Heap(values) => values,
            #[cfg(target_os = "linux")]
            Storage::Mapped { map, offset, len } => {
                bytemuck::cast_slice_mut(&mut map[*offset..*offset + *len * std::mem::size_of::<T>()])
            }
        }
    }
}

impl<T: Pod> Deref for HugePageArray<T> {
    type Target = [T];

    #[inline(always)]
    fn deref(&self) -> &[T] {
        match &self.storage {
            Storage::Heap(values) => values,
            #[cfg(target_os = "linux")]
            Storage::Mapped { map, offset, len } => {
                bytemuck::cast_slice(&map[*offset..*offset + *len * std::mem::size_of::<T>()])
            }
        }
    }
}

impl<T: Pod> Clone for HugePageArray<T> {
    fn clone(&self) -> Self {
        Self::new(self.to_vec())
    }
}

impl<T: Pod + fmt::Debug> fmt::Debug for HugePageArray<T> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_list().entries(self.iter()).finish()
    }
}

impl<T: Pod> Default for HugePageArray<T> {
    fn default() -> Self {
        Self::new(Vec::new())
    }
}

impl<T: Pod> From<Vec<T>> for HugePageArray<T> {
    fn from(values: Vec<T>) -> Self {
        Self::new(values)
    }
}

/// Bytes of this process's memory that the kernel currently backs with
/// transparent huge pages (`AnonHugePages` in `/proc/self/smaps_rollup`), or
/// `None` where that is not known. For reports and benchmarks.
pub fn huge_page_bytes() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/self/smaps_rollup").ok()?;
    let line = text.lines().find(|l| l.starts_with("AnonHugePages:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024)
}

/// Asks for the cache line holding `x` without waiting for it, so that the
/// miss overlaps with work already at hand. A no-op where there is no
/// prefetch instruction.
#[inline(always)]
pub(crate) fn prefetch<T>(x: &T) {
    #[cfg(all(target_arch = "x86_64", target_feature = "sse"))]
    safe_arch::prefetch_t0(x);
    #[cfg(not(all(target_arch = "x86_64", target_feature = "sse")))]
    let _ = x;
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn small_arrays_stay_on_the_heap_and_read_back() {
        let values: Vec<u32> = (0..1000).collect();
        let array = HugePageArray::new(values.clone());
        assert!(!array.is_mapped());
        assert_eq!(&array[..], &values[..]);
        assert_eq!(array.clone()[..], values[..]);
        assert!(HugePageArray::<u32>::default().is_empty());
    }

    #[test]
    fn large_arrays_are_mapped_on_a_2_mib_boundary_and_read_back() {
        // 12 MiB of distinct values, so a wrong offset or length shows.
        let values: Vec<[u32; 4]> = (0..(12 << 20) / 16).map(|i| [i, !i, i * 7, i ^ 0x55]).collect();
        let array = HugePageArray::new(values.clone());
        if cfg!(target_os = "linux") {
            assert!(array.is_mapped());
            assert_eq!(array.as_ptr() as usize % HUGE_PAGE, 0);
        }
        assert_eq!(array.len(), values.len());
        assert!(array[..] == values[..]);
        let copy = array.clone();
        assert!(copy[..] == values[..]);
        assert_ne!(copy.as_ptr(), array.as_ptr());
    }

    /// The `VmFlags` of the mapping holding `address`, from `/proc/self/smaps`.
    #[cfg(target_os = "linux")]
    fn vm_flags(address: usize) -> String {
        let smaps = std::fs::read_to_string("/proc/self/smaps").unwrap();
        let mut inside = false;
        for line in smaps.lines() {
            let range = line.split_whitespace().next().and_then(|r| r.split_once('-'));
            if let Some((start, end)) = range
                && let (Ok(start), Ok(end)) = (usize::from_str_radix(start, 16), usize::from_str_radix(end, 16))
            {
                inside = (start..end).contains(&address);
            } else if inside && let Some(flags) = line.strip_prefix("VmFlags:") {
                return flags.to_string();
            }
        }
        panic!("no mapping holds {address:#x}");
    }

    /// An array filled in place is advised for huge pages only once it is
    /// written (`hg` in its mapping's flags): advised before, every first
    /// write would wait for a huge page (see the module documentation).
    #[cfg(target_os = "linux")]
    #[test]
    fn huge_pages_are_asked_for_once_the_array_is_written() {
        let mut array = HugePageVec::with_capacity((12 << 20) / 16);
        for i in 0..(12 << 20) / 16 {
            array.push([i as u32; 4]);
        }
        let address = array.as_mut_slice().as_ptr() as usize;
        assert!(!vm_flags(address).contains(" hg"), "advised while filling");
        let array = array.finish();
        assert!(array.is_mapped());
        assert!(vm_flags(address).contains(" hg"), "not advised once filled");
        let copied = HugePageArray::new(array.to_vec());
        assert!(vm_flags(copied.as_ptr() as usize).contains(" hg"));
    }

    #[test]
    fn arrays_filled_in_place_read_back_mapped_or_not() {
        // Large and small capacities; filled exactly, partly, and past the
        // capacity (which moves to the heap); then changed in place.
        let big = (12 << 20) / 16;
        for (capacity, count) in [(big, big), (big, 1000), (big, big + 5), (100, 100), (100, 250), (0, 3)] {
            let mut array = HugePageVec::with_capacity(capacity);
            let values: Vec<[u32; 4]> = (0..count as u32).map(|i| [i, !i, i * 7, i ^ 0x55]).collect();
            for &v in &values {
                array.push(v);
            }
            assert_eq!(array.len(), count);
            array.as_mut_slice()[count / 2][0] = 1234;
            let mut expected = values.clone();
            expected[count / 2][0] = 1234;
            let array = array.finish();
            assert!(array[..] == expected[..], "capacity {capacity}, {count} pushed");
            if cfg!(target_os = "linux") {
                assert_eq!(
                    array.is_mapped(),
                    capacity == big && count <= big,
                    "capacity {capacity}, {count} pushed"
                );
            }
        }
    }
}
