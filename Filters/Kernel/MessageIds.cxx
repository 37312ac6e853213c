// SPDX-License-Identifier: GPL-3.0-or-later
#include "MessageIds.h"

namespace ctk
{
MessageBuilder& MessageBuilder::Named(IdKind kind, Id value)
{
  const std::string digits = std::to_string(value);
  MessageId id;
  id.Offset = static_cast<std::size_t>(static_cast<std::streamoff>(this->Stream.tellp()));
  id.Length = digits.size();
  id.Kind = kind;
  id.Value = value;
  this->Written.push_back(id);
  this->Stream << digits;
  return *this;
}

std::string RenameIds(const std::string& message, const std::vector<MessageId>& ids,
  const std::function<Id(IdKind, Id)>& name)
{
  std::string out;
  std::size_t at = 0;
  for (const MessageId& id : ids) // in the order written: increasing offsets
  {
    if (id.Offset < at || id.Offset > message.size() ||
      message.compare(id.Offset, id.Length, std::to_string(id.Value)) != 0)
    {
      return message;
    }
    out.append(message, at, id.Offset - at);
    out += std::to_string(name(id.Kind, id.Value));
    at = id.Offset + id.Length;
  }
  out.append(message, at, std::string::npos);
  return out;
}
} // namespace ctk
