// Must not compile with -Werror=unused-result: pm::Status is [[nodiscard]], and so is
// read_pm. run.sh checks that building this fails, and fails for that reason.
#include <pm/pm_codec.h>

int main() {
  pm::ProgressiveMesh progressive;
  pm::read_pm("not a stream", progressive);
  return 0;
}
