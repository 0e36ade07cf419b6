#include "odocal/hal/linux_gpiod/setup_result.hpp"

#include <cerrno>

namespace odocal::hal::linux_gpiod {

SetupCode code_of_errno(int error_number) {
  switch (error_number) {
    case ENOENT:
    case ENODEV:
    case ENXIO:
      return SetupCode::not_found;
    case EBUSY:
      return SetupCode::busy;
    case EACCES:
    case EPERM:
      return SetupCode::permission_denied;
    case EINVAL:
    case ERANGE:
      return SetupCode::bad_argument;
    default:
      return SetupCode::system_error;
  }
}

}  // namespace odocal::hal::linux_gpiod
