// Background priority for helper threads: see background_priority.hpp.
#include "app/background_priority.hpp"

#include <pthread.h>
#include <sched.h>
#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

namespace acdr {

bool lower_this_threads_priority() {
  sched_param param{};
  param.sched_priority = 0;
  const bool batch = pthread_setschedparam(pthread_self(), SCHED_BATCH, &param) == 0;
  const bool nice = setpriority(PRIO_PROCESS, static_cast<id_t>(syscall(SYS_gettid)), 10) == 0;
  return batch && nice;
}

}  // namespace acdr
