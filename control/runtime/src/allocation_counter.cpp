// Counts, per thread, how often the heap is used: every malloc-family call, so C++'s operator new
// and C code (ViSP's vpArray2D, LAPACK) alike. One place counts, the malloc family, so a `new`
// (replaced at the end of this file to call malloc) is one allocation, never two.
//
// Normal builds define glibc's allocation entry points here, in the executable (the operator new
// links this object into every program that links the runtime, and executables export the
// definitions to the shared libraries), each counting and forwarding to glibc's own __libc_*
// allocator: the heap stays glibc's, so memory from either side may be freed by the other. Valgrind
// replaces these definitions as it replaces glibc's (it sees every block; the counters then see
// none). A sanitizer owns malloc instead (defining it here would hide every allocation from it),
// and it calls hooks after each allocation and before each free: there they count
// (ThreadSanitizer's runtime in GCC 12 calls none for the aligned allocations; AddressSanitizer's
// calls them all).
//
// The counters are initial-exec thread_locals: a fixed offset from the thread pointer, set up with
// the thread before any code of it runs, so malloc may touch them at any time (during thread
// start-up, TLS set-up, from the dynamic loader), where a __tls_get_addr call could itself
// allocate.
#include "cambio/runtime/allocation_counter.hpp"

#include <cstddef>
#include <cstdlib>
#include <new>

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define CAMBIO_SANITIZER_OWNS_MALLOC 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer) || \
    __has_feature(memory_sanitizer) || __has_feature(hwaddress_sanitizer)
#define CAMBIO_SANITIZER_OWNS_MALLOC 1
#endif
#endif

#ifdef CAMBIO_SANITIZER_OWNS_MALLOC
#if __has_include(<sanitizer/allocator_interface.h>)
#include <sanitizer/allocator_interface.h>
#else
// GCC 12 ships no allocator_interface.h, but its sanitizer runtimes export the hook (LLVM's
// declaration).
using SanitizerMallocHook = void (*)(const volatile void*, std::size_t);
using SanitizerFreeHook = void (*)(const volatile void*);
extern "C" int __sanitizer_install_malloc_and_free_hooks(SanitizerMallocHook, SanitizerFreeHook);
#endif
#else
#include <malloc.h>  // The declarations the replacements below must match.

#include <cerrno>
#endif

namespace {
__attribute__((tls_model("initial-exec"))) thread_local std::uint64_t g_thread_allocations = 0;
__attribute__((tls_model("initial-exec"))) thread_local std::uint64_t g_thread_frees = 0;
}  // namespace

namespace cambio::runtime {
std::uint64_t thread_allocation_count() noexcept {
  return g_thread_allocations;
}
std::uint64_t thread_free_count() noexcept {
  return g_thread_frees;
}
}  // namespace cambio::runtime

#ifdef CAMBIO_SANITIZER_OWNS_MALLOC

namespace {
// Called by the sanitizer's allocator for each block it hands out (malloc, calloc, memalign,
// operator new; realloc as a new block and a freed one) and each block it takes back.
void count_allocation(const volatile void*, std::size_t) {
  ++g_thread_allocations;
}
void count_free(const volatile void*) {
  ++g_thread_frees;
}
// Installed while this object's statics are initialized, before main().
[[maybe_unused]] const int g_hooks_installed =
    __sanitizer_install_malloc_and_free_hooks(count_allocation, count_free);
}  // namespace

#else

// glibc's allocator under the names it exports for this purpose (not declared in its headers).
extern "C" {
void* __libc_malloc(std::size_t size);
void* __libc_calloc(std::size_t count, std::size_t size);
void* __libc_realloc(void* p, std::size_t size);
void __libc_free(void* p);
void* __libc_memalign(std::size_t alignment, std::size_t size);
void* __libc_valloc(std::size_t size);
void* __libc_pvalloc(std::size_t size);
}

// The replacements, with glibc's signatures (<stdlib.h>, <malloc.h>). As under a sanitizer, a
// realloc counts as the allocation of its new block and the free of its old one, and free(NULL)
// counts as nothing.
extern "C" {
void* malloc(std::size_t size) noexcept {
  ++g_thread_allocations;
  return __libc_malloc(size);
}
void* calloc(std::size_t count, std::size_t size) noexcept {
  ++g_thread_allocations;
  return __libc_calloc(count, size);
}
void* realloc(void* p, std::size_t size) noexcept {
  if (p == nullptr || size != 0) ++g_thread_allocations;  // realloc(p, 0) only frees p.
  if (p != nullptr) ++g_thread_frees;
  return __libc_realloc(p, size);
}
void free(void* p) noexcept {
  if (p != nullptr) ++g_thread_frees;
  __libc_free(p);
}
void* memalign(std::size_t alignment, std::size_t size) noexcept {
  ++g_thread_allocations;
  return __libc_memalign(alignment, size);
}
void* aligned_alloc(std::size_t alignment, std::size_t size) noexcept {
  ++g_thread_allocations;
  return __libc_memalign(alignment, size);
}
int posix_memalign(void** out, std::size_t alignment, std::size_t size) noexcept {
  // POSIX: a power of two multiple of sizeof(void*), else EINVAL and *out untouched.
  if (alignment % sizeof(void*) != 0 || (alignment & (alignment - 1)) != 0 || alignment == 0) {
    return EINVAL;
  }
  ++g_thread_allocations;
  void* p = __libc_memalign(alignment, size);
  if (p == nullptr) return ENOMEM;
  *out = p;
  return 0;
}
void* valloc(std::size_t size) noexcept {
  ++g_thread_allocations;
  return __libc_valloc(size);
}
void* pvalloc(std::size_t size) noexcept {
  ++g_thread_allocations;
  return __libc_pvalloc(size);
}
}

#endif

// operator new and delete on malloc and free, in every build: the counting above sees them, and
// this object is linked into every program that links the runtime (each one needs operator new).
// Under a sanitizer they reach its malloc and free (so it does not match a new with its delete).
namespace {
void* allocate(std::size_t size) {
  if (size == 0) size = 1;
  if (void* p = std::malloc(size)) return p;
  throw std::bad_alloc();
}
void* allocate_aligned(std::size_t size, std::align_val_t alignment) {
  const auto align = static_cast<std::size_t>(alignment);
  const std::size_t rounded = ((size == 0 ? 1 : size) + align - 1) / align * align;
  if (void* p = std::aligned_alloc(align, rounded)) return p;
  throw std::bad_alloc();
}
}  // namespace

void* operator new(std::size_t size) {
  return allocate(size);
}
void* operator new[](std::size_t size) {
  return allocate(size);
}
void* operator new(std::size_t size, const std::nothrow_t&) noexcept {
  try {
    return allocate(size);
  } catch (...) {
    return nullptr;
  }
}
void* operator new[](std::size_t size, const std::nothrow_t&) noexcept {
  try {
    return allocate(size);
  } catch (...) {
    return nullptr;
  }
}
void* operator new(std::size_t size, std::align_val_t alignment) {
  return allocate_aligned(size, alignment);
}
void* operator new[](std::size_t size, std::align_val_t alignment) {
  return allocate_aligned(size, alignment);
}
void operator delete(void* p) noexcept {
  std::free(p);
}
void operator delete[](void* p) noexcept {
  std::free(p);
}
void operator delete(void* p, std::size_t) noexcept {
  std::free(p);
}
void operator delete[](void* p, std::size_t) noexcept {
  std::free(p);
}
void operator delete(void* p, std::align_val_t) noexcept {
  std::free(p);
}
void operator delete[](void* p, std::align_val_t) noexcept {
  std::free(p);
}
void operator delete(void* p, std::size_t, std::align_val_t) noexcept {
  std::free(p);
}
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept {
  std::free(p);
}
