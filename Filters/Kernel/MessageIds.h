// SPDX-License-Identifier: GPL-3.0-or-later
// Error messages that name triangles and vertices by the kernel's ids, recording where they do:
// a caller that numbers them otherwise (a filter that dropped repeated ghost cells or renumbered
// the mesh into its locality order) renames them, and its message names its own cells and points.
#ifndef CTSplines_Kernel_MessageIds_h
#define CTSplines_Kernel_MessageIds_h

#include <cstddef>
#include <cstdint>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

namespace ctk
{
using Id = std::int64_t;

/// What an id written into a message names.
enum class IdKind : unsigned char
{
  Triangle,
  Vertex
};

/// An id written into a message, as the characters Message[Offset, Offset + Length).
struct MessageId
{
  std::size_t Offset = 0, Length = 0;
  IdKind Kind = IdKind::Triangle;
  Id Value = -1;
};

/// Tags for MessageBuilder: a triangle's or a vertex's id.
struct TriangleId
{
  Id Value;
};
struct VertexId
{
  Id Value;
};

/// An ostringstream that records where it writes TriangleId and VertexId (plain numbers, e.g.
/// counts or ids out of range, are text).
class MessageBuilder
{
public:
  template <typename T>
  MessageBuilder& operator<<(const T& x)
  {
    this->Stream << x;
    return *this;
  }
  MessageBuilder& operator<<(TriangleId t) { return this->Named(IdKind::Triangle, t.Value); }
  MessageBuilder& operator<<(VertexId v) { return this->Named(IdKind::Vertex, v.Value); }

  std::string Text() const { return this->Stream.str(); }
  const std::vector<MessageId>& Ids() const { return this->Written; }

  /// A failed status (BuildStatus, TopologyStatus) with this message.
  template <typename Status>
  Status Failure() const
  {
    Status status;
    status.Ok = false;
    status.Message = this->Text();
    status.Ids = this->Written;
    return status;
  }

private:
  MessageBuilder& Named(IdKind kind, Id value);

  std::ostringstream Stream;
  std::vector<MessageId> Written;
};

/// message with each recorded id replaced by name(kind, id). Returns message unchanged if the
/// ids do not match it (text added before them since, say).
std::string RenameIds(const std::string& message, const std::vector<MessageId>& ids,
  const std::function<Id(IdKind, Id)>& name);

} // namespace ctk

#endif
