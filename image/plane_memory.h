#pragma once
// How the process hands frame planes back to the allocator. A plane is one float per
// pixel: 230 KB at 320x180, 8 MB at 1920x1080. glibc serves blocks of that size with mmap
// and returns them to the kernel when freed, so every plane a task allocates arrives as
// fresh pages, each one a page fault on first touch. A filter task decodes and allocates
// hundreds of planes, and on a virtual machine those faults cost more than the decoding
// itself (a 154-channel 320x180 frame: 0.21 s to decode with fresh pages, 0.09 s with
// reused ones; docs/performance.md).
namespace pathfarm {

// Serves blocks below 64 MB (a float plane up to 4K) from the heap, and keeps up to 512 MB
// of freed heap for the next allocations instead of returning it to the kernel. Call once,
// early in main; returns false when the allocator refused a setting (not glibc's).
bool keepFreedPlanesForReuse();

// Gives the heap's freed memory back to the kernel when it holds more than those 512 MB:
// the trim threshold only shrinks the heap's top, and what a large task freed below a
// block still in use would stay resident for good. Nothing on another allocator.
void returnFreedBeyondReuse();

}  // namespace pathfarm
