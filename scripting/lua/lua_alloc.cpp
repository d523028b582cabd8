// The robots' Lua states' arenas (lua_alloc.h).
#include "scripting/lua/lua_alloc.h"

#include <sys/mman.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <new>
#include <vector>

#if defined(__SANITIZE_ADDRESS__)
#define COLONY_LUA_PLAIN_ALLOCATOR 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define COLONY_LUA_PLAIN_ALLOCATOR 1
#endif
#endif

namespace colony::lua {

#ifdef COLONY_LUA_PLAIN_ALLOCATOR

// Under AddressSanitizer the C library's allocator is kept, so that the
// sanitizer sees every Lua object.
lua_State* NewArenaState() { return luaL_newstate(); }
void CloseArenaState(lua_State* L) { lua_close(L); }
void SetColdAllocation(lua_State*, bool) {}
void SetFreshAllocation(lua_State*, bool) {}

#else

namespace {

constexpr size_t kChunkBytes = size_t{32} << 10;   // what an arena takes at a time
constexpr size_t kRegionBytes = size_t{64} << 20;  // what the pool maps at a time
constexpr size_t kHugePage = size_t{2} << 20;

// Size classes of the small objects (up to 4 KB): 16-byte steps to 256,
// 128-byte steps to 1 KB, 512-byte steps to 4 KB. Larger objects (big
// tables' parts, long strings) come from the C library.
constexpr size_t kSmallest = 16;
constexpr size_t kMaxSmall = 4096;
constexpr int kClasses = 16 + 6 + 6;

int ClassOf(size_t size) {
  if (size <= 256) return static_cast<int>((std::max(size, kSmallest) + 15) / 16) - 1;
  if (size <= 1024) return 16 + static_cast<int>((size - 257) / 128);
  return 22 + static_cast<int>((size - 1025) / 512);
}

size_t ClassSize(int c) {
  if (c < 16) return 16 * static_cast<size_t>(c + 1);
  if (c < 22) return 384 + 128 * static_cast<size_t>(c - 16);
  return 1536 + 512 * static_cast<size_t>(c - 22);
}

// Memory for every arena of the process, in chunks, from regions mapped as
// needed and asked to be backed by huge pages. A closed state's chunks return
// here for the next state; when the last state is closed (a simulation torn
// down), the regions are unmapped, so the memory goes back to the system.
class Pool {
 public:
  void* Take() {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!free_.empty()) {
      void* chunk = free_.back();
      free_.pop_back();
      ++taken_;
      return chunk;
    }
    if (next_ == end_) {
      void* region = mmap(nullptr, kRegionBytes + kHugePage, PROT_READ | PROT_WRITE,
                          MAP_PRIVATE | MAP_ANONYMOUS | MAP_NORESERVE, -1, 0);
      if (region == MAP_FAILED) return nullptr;
      try {
        regions_.push_back(region);
      } catch (const std::bad_alloc&) {
        munmap(region, kRegionBytes + kHugePage);
        return nullptr;
      }
      const auto at = reinterpret_cast<uintptr_t>(region);
      next_ = reinterpret_cast<char*>((at + kHugePage - 1) & ~(kHugePage - 1));
      end_ = next_ + kRegionBytes;
      // A hint: where the kernel gives no huge pages, small ones serve.
      madvise(next_, kRegionBytes, MADV_HUGEPAGE);
    }
    void* chunk = next_;
    next_ += kChunkBytes;
    ++taken_;
    return chunk;
  }
  void Give(const std::vector<void*>& chunks) {
    std::lock_guard<std::mutex> lock(mutex_);
    taken_ -= chunks.size();
    if (taken_ > 0) {
      try {
        free_.insert(free_.end(), chunks.begin(), chunks.end());
      } catch (const std::bad_alloc&) {
        // Out of memory: those chunks stay unused until the regions go.
      }
      return;
    }
    for (void* region : regions_) munmap(region, kRegionBytes + kHugePage);
    regions_.clear();
    free_.clear();
    next_ = end_ = nullptr;
  }

 private:
  std::mutex mutex_;
  std::vector<void*> regions_;  // as mapped
  std::vector<void*> free_;
  size_t taken_ = 0;  // chunks held by arenas
  char* next_ = nullptr;
  char* end_ = nullptr;
};

Pool& ThePool() {
  static Pool* pool = new Pool;  // never destroyed: states may close at exit
  return *pool;
}

// One state's objects. Used by one thread at a time (the one stepping that
// robot), as its Lua state is.
class Arena {
 public:
  ~Arena() { ThePool().Give(chunks_); }

  void* Allocate(size_t size) {
    if (size > kMaxSmall) return std::malloc(size);
    const int c = ClassOf(size);
    if (void* block = free_[c]; block != nullptr && !fresh_) {
      free_[c] = *static_cast<void**>(block);
      return block;
    }
    const size_t bytes = ClassSize(c);
    Run& run = runs_[cold_];
    if (static_cast<size_t>(run.end - run.next) < bytes) {
      void* chunk = ThePool().Take();
      if (chunk == nullptr) return nullptr;
      try {
        chunks_.push_back(chunk);
      } catch (const std::bad_alloc&) {
        ThePool().Give({chunk});
        return nullptr;
      }
      run.next = static_cast<char*>(chunk);
      run.end = run.next + kChunkBytes;
    }
    void* block = run.next;
    run.next += bytes;
    return block;
  }

  void SetCold(bool cold) { cold_ = cold ? 1 : 0; }
  void SetFresh(bool fresh) { fresh_ = fresh; }

  void Free(void* block, size_t size) {
    if (size > kMaxSmall) {
      std::free(block);
      return;
    }
    const int c = ClassOf(size);
    *static_cast<void**>(block) = free_[c];
    free_[c] = block;
  }

  // lua_Alloc's contract: `size` is the block's old size when `block` is
  // not null; a new size of 0 frees; a shrink must not fail.
  void* Reallocate(void* block, size_t old_size, size_t new_size) {
    const bool old_small = old_size <= kMaxSmall, new_small = new_size <= kMaxSmall;
    if (!old_small && !new_small) return std::realloc(block, new_size);
    // Within the small classes a shrink keeps its block (it is freed later
    // into the smaller size's class, which it is large enough for), as does
    // a growth within the same class.
    if (old_small && new_small && (new_size <= old_size || ClassOf(new_size) == ClassOf(old_size)))
      return block;
    void* moved = Allocate(new_size);
    if (moved == nullptr) {
      // Only a shrink from a large block to a small one may not fail: keep
      // the large block, which then counts as small (its memory is not
      // returned to the C library, a leak only when memory is exhausted).
      return new_size < old_size ? block : nullptr;
    }
    std::memcpy(moved, block, std::min(old_size, new_size));
    Free(block, old_size);
    return moved;
  }

 private:
  void* free_[kClasses] = {};
  // Where new small objects go: the rest of the last chunk taken for objects
  // visited often ([0]) or seldom ([1]), so that the former lie together.
  struct Run {
    char* next = nullptr;
    char* end = nullptr;
  };
  Run runs_[2];
  int cold_ = 0;
  bool fresh_ = false;  // new objects in order, none in freed blocks
  std::vector<void*> chunks_;
};

void* ArenaAlloc(void* ud, void* block, size_t old_size, size_t new_size) {
  auto* arena = static_cast<Arena*>(ud);
  if (new_size == 0) {
    if (block != nullptr) arena->Free(block, old_size);
    return nullptr;
  }
  if (block == nullptr) return arena->Allocate(new_size);  // old_size is a type tag then
  return arena->Reallocate(block, old_size, new_size);
}

// As luaL_newstate's: print the error of an unprotected call before Lua aborts.
int Panic(lua_State* L) {
  const char* message = lua_tostring(L, -1);
  std::fprintf(stderr, "colony: error: Lua: unprotected error: %s\n",
               message ? message : "(not a string)");
  return 0;
}

}  // namespace

lua_State* NewArenaState() {
  auto* arena = new (std::nothrow) Arena;
  if (arena == nullptr) return nullptr;
  lua_State* L = lua_newstate(ArenaAlloc, arena);
  if (L == nullptr) {
    delete arena;
    return nullptr;
  }
  lua_atpanic(L, Panic);
  return L;
}

void SetColdAllocation(lua_State* L, bool cold) {
  void* ud = nullptr;
  lua_getallocf(L, &ud);
  static_cast<Arena*>(ud)->SetCold(cold);
}

void SetFreshAllocation(lua_State* L, bool fresh) {
  void* ud = nullptr;
  lua_getallocf(L, &ud);
  static_cast<Arena*>(ud)->SetFresh(fresh);
}

void CloseArenaState(lua_State* L) {
  void* ud = nullptr;
  lua_getallocf(L, &ud);
  lua_close(L);
  delete static_cast<Arena*>(ud);
}

#endif

}  // namespace colony::lua
