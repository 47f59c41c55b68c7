// The one list of camera function types. Adding a function = one line here.
#include <algorithm>

#include "camera/dir_basic.h"
#include "camera/functions.h"
#include "camera/org_basic.h"

namespace anamorph {

namespace {
const OrgFunctionInfo* const kOrg[] = {&kPointOrgInfo, &kPlaneOrgInfo};
const DirFunctionInfo* const kDir[] = {&kConstantDirInfo, &kFromSurfaceDirInfo};

std::vector<OrgFunctionInfo> org_list() {
  std::vector<OrgFunctionInfo> v;
  for (auto* i : kOrg) v.push_back(*i);
  return v;
}
std::vector<DirFunctionInfo> dir_list() {
  std::vector<DirFunctionInfo> v;
  for (auto* i : kDir) v.push_back(*i);
  return v;
}
}  // namespace

std::span<const OrgFunctionInfo> org_functions() {
  static const std::vector<OrgFunctionInfo> list = org_list();
  return list;
}
std::span<const DirFunctionInfo> dir_functions() {
  static const std::vector<DirFunctionInfo> list = dir_list();
  return list;
}
const OrgFunctionInfo* find_org_function(std::string_view name) {
  for (const auto& f : org_functions())
    if (f.name == name) return &f;
  return nullptr;
}
const DirFunctionInfo* find_dir_function(std::string_view name) {
  for (const auto& f : dir_functions())
    if (f.name == name) return &f;
  return nullptr;
}

}  // namespace anamorph
