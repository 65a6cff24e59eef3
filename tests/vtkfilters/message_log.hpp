#pragma once
/// \file message_log.hpp
/// Records the errors and warnings a VTK object reports (vtkErrorMacro, vtkWarningMacro)
/// instead of printing them, so that tests can assert on them.

#include <vtkCallbackCommand.h>
#include <vtkCommand.h>
#include <vtkNew.h>
#include <vtkObject.h>

#include <string>
#include <vector>

namespace hexdem::testing {

class MessageLog {
 public:
  explicit MessageLog(vtkObject* object) {
    observer_->SetClientData(this);
    observer_->SetCallback([](vtkObject*, unsigned long event, void* client, void* call) {
      auto* log = static_cast<MessageLog*>(client);
      const std::string text = call ? static_cast<const char*>(call) : "";
      (event == vtkCommand::ErrorEvent ? log->errors : log->warnings).push_back(text);
    });
    object->AddObserver(vtkCommand::ErrorEvent, observer_);
    object->AddObserver(vtkCommand::WarningEvent, observer_);
  }

  /// True when some error contains `part`.
  bool has_error(const std::string& part) const { return contains(errors, part); }
  bool has_warning(const std::string& part) const { return contains(warnings, part); }

  std::vector<std::string> errors;
  std::vector<std::string> warnings;

 private:
  static bool contains(const std::vector<std::string>& list, const std::string& part) {
    for (const auto& m : list) {
      if (m.find(part) != std::string::npos) return true;
    }
    return false;
  }
  vtkNew<vtkCallbackCommand> observer_;
};

}  // namespace hexdem::testing
