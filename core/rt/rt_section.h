#pragma once
// The real-time path, marked where it runs: a loop thread holds an RtSection from a sample's
// arrival to its answer sent and its record handed over. Inside, the code allocates nothing,
// locks nothing, never blocks and reads no file: tests count what happens inside the marked
// sections of any thread (tests/support/alloc_guard.h, file_guard.h), so the guard holds on a
// whole node as its process runs it, not on a copy of its loop.
namespace enact::rt {

inline thread_local bool in_rt_section = false;

// where a section's ends are not one scope's
inline void enter_rt_section() noexcept { in_rt_section = true; }
inline void leave_rt_section() noexcept { in_rt_section = false; }

class RtSection {
 public:
  RtSection() noexcept { in_rt_section = true; }
  ~RtSection() { in_rt_section = false; }
  RtSection(const RtSection&) = delete;
  RtSection& operator=(const RtSection&) = delete;
};

}  // namespace enact::rt
