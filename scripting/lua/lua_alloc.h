// The memory of the robots' Lua states (scripting/lua/BENCHMARK-NOTES.md).
//
// With one Lua state per robot, a swarm of 10,000 holds some 500 MB of Lua
// objects, and every step visits a few kilobytes of each state: its stack,
// globals, `robot` tables and the script's own. From the C library's
// allocator those objects are scattered over the whole heap in 4 KB pages, so
// at that size nearly every visit misses both the cache and the TLB. Here
// every state allocates its small objects from its own run of memory, carved
// out of large regions the kernel may back with 2 MB pages: a robot's objects
// sit together and the whole swarm's spans a few hundred TLB entries.
//
// The allocator only decides where objects live. Lua's garbage collector
// counts the sizes it asks for, not what is reserved, so when a collection
// runs, and so every result, is the same as with the C library's allocator.
#pragma once

#include <lua.hpp>

namespace colony::lua {

// A new Lua state whose allocations go through its own arena (under
// AddressSanitizer: luaL_newstate's, so the sanitizer sees every object).
// Returns nullptr when out of memory.
lua_State* NewArenaState();
// From now on, new objects of the state go to a run of memory of their own
// (cold) or to the run of the objects a step visits (not cold, the default):
// each robot's standard library copies, visited seldom, are made cold so
// that the objects its step reads lie close to the next robot's.
void SetColdAllocation(lua_State* L, bool cold);
// While `fresh`, new small objects are laid one after the other in new
// memory, never in blocks freed before: a robot's tables made at its start
// then lie together (a table beside its hash part), in the order its step
// reads them.
void SetFreshAllocation(lua_State* L, bool fresh);
// Closes a state made by NewArenaState, and frees its arena.
void CloseArenaState(lua_State* L);

}  // namespace colony::lua
