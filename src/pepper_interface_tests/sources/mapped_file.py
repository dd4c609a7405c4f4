"""A recording file mapped read-only, for the readers that hand messages over in place
(bag_chunks.py, mcap_chunks.py): one mapping, each chunk a view of it.

span() is the one way in, and does two things before it hands a chunk over:
  * the file's size now: a file cut short since it was mapped would make a read of a mapped page
    past its new end a SIGBUS, so a chunk past the end is None and the reader raises its
    library's own error for a truncated file (a frame held from before a cut and read after it
    is not guarded: nothing else cuts a recording while sensorTest reads it);
  * every page before the chunk is unmapped (madvise MADV_DONTNEED): the pages stay in the page
    cache, a view still held (a camera's previous frame, a frame waiting for the motion check)
    reads them again from there and is unmapped again at the next chunk, so the process holds
    about the chunk being read, not what it has read (recorders write chunks in time order). A
    range already unmapped costs the kernel a walk of empty page tables, not of pages.
"""
import mmap
import os
from typing import Optional


class MappedFile:
    def __init__(self, fd: int) -> None:
        self.fd = fd
        self.map: Optional[mmap.mmap] = None        # mapped at the first span

    def span(self, start: int, end: int) -> Optional[memoryview]:
        """The bytes [start, end) of the file, the pages before `start` unmapped; None when the
        file now ends before `end`."""
        if self.map is None:
            self.map = mmap.mmap(self.fd, 0, access=mmap.ACCESS_READ)
        if end > min(len(self.map), os.fstat(self.fd).st_size):
            return None
        page = start // mmap.PAGESIZE * mmap.PAGESIZE
        if page > 0 and hasattr(self.map, 'madvise'):
            self.map.madvise(mmap.MADV_DONTNEED, 0, page)
        return memoryview(self.map)[start:end]
