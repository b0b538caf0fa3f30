#include "core/errors.h"

#include <new>

namespace brdf {

int ExitStatus(const std::exception_ptr& error, std::string* message) {
  try {
    std::rethrow_exception(error);
  } catch (const Error& failure) {
    *message = failure.what();
    return failure.exit_status();
  } catch (const std::bad_alloc&) {
    *message = "out of memory";
  } catch (const std::exception& failure) {
    *message = std::string("internal error: ") + failure.what();
  } catch (...) {
    *message = "internal error: unknown exception";
  }
  return 1;
}

}  // namespace brdf
