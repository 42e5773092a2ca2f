/**
 * @file roles.cpp
 * @brief Storage of the role configurations the task tables point to.
 */
#include "trn/tasks/roles.hpp"

namespace trn::tasks {

udn::EndpointConfig g_endpoint_config{};
IoTaskConfig g_io_role_config{};
FilterTaskConfig g_filter_role_config{};

}  // namespace trn::tasks
