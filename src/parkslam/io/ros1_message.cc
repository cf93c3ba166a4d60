#include "parkslam/io/ros1_message.h"

#include <algorithm>
#include <cstring>
#include <optional>
#include <set>
#include <stdexcept>

#include "parkslam/io/text_util.h"

namespace parkslam::io::ros1 {
namespace {

// Size in bytes of each fixed-size primitive.
int PrimitiveSize(std::string_view type) {
  if (type == "bool" || type == "int8" || type == "uint8" || type == "byte" || type == "char")
    return 1;
  if (type == "int16" || type == "uint16") return 2;
  if (type == "int32" || type == "uint32" || type == "float32") return 4;
  if (type == "int64" || type == "uint64" || type == "float64" || type == "time" ||
      type == "duration")
    return 8;
  return 0;
}

bool IsPrimitive(std::string_view type) { return PrimitiveSize(type) > 0 || type == "string"; }

std::string Resolve(const std::string& type, const std::string& package) {
  if (IsPrimitive(type) || type.find('/') != std::string::npos) return type;
  if (type == "Header") return "std_msgs/Header";
  return package + "/" + type;
}

std::string PackageOf(const std::string& type) {
  const std::size_t slash = type.find('/');
  return slash == std::string::npos ? std::string() : type.substr(0, slash);
}

class Reader {
 public:
  Reader(const MessageSpec& spec, const std::uint8_t* data, std::size_t size,
         const std::function<void(const Leaf&)>& visit)
      : spec_(spec), data_(data), size_(size), visit_(visit) {}

  void Message(const std::string& type, const std::string& prefix, int depth) {
    if (depth > 32) throw std::invalid_argument("ros1: message nesting deeper than 32");
    const auto it = spec_.types.find(type);
    if (it == spec_.types.end()) throw std::invalid_argument("ros1: no definition of " + type);
    for (const Field& f : it->second) {
      const std::string path = prefix.empty() ? f.name : prefix + "." + f.name;
      if (!f.is_array) {
        Value(f.type, path, depth);
        continue;
      }
      const std::size_t count =
          f.fixed_length >= 0 ? static_cast<std::size_t>(f.fixed_length) : Uint32();
      if (f.type == "uint8" || f.type == "byte" || f.type == "char") {
        Leaf leaf;
        leaf.path = path;
        leaf.kind = Leaf::kBytes;
        leaf.bytes = Take(count);
        leaf.size = count;
        visit_(leaf);
        continue;
      }
      // Every element takes at least one byte: a count beyond the rest is
      // corrupt, not a reason to loop for long.
      if (count > size_ - offset_) throw std::invalid_argument("ros1: array longer than the data");
      for (std::size_t i = 0; i < count; ++i) {
        Value(f.type, path + "[" + std::to_string(i) + "]", depth);
      }
    }
  }

  void Finish() const {
    if (offset_ != size_) {
      throw std::invalid_argument("ros1: " + std::to_string(size_ - offset_) +
                                  " bytes left over after the message");
    }
  }

 private:
  const std::uint8_t* Take(std::size_t n) {
    if (n > size_ - offset_) throw std::invalid_argument("ros1: the message ends early");
    const std::uint8_t* p = data_ + offset_;
    offset_ += n;
    return p;
  }
  template <typename T>
  T Get() {
    T value;
    std::memcpy(&value, Take(sizeof(T)), sizeof(T));  // ROS 1 is little-endian, as is x86
    return value;
  }
  std::uint32_t Uint32() { return Get<std::uint32_t>(); }

  void Value(const std::string& type, const std::string& path, int depth) {
    if (!IsPrimitive(type)) {
      Message(type, path, depth + 1);
      return;
    }
    Leaf leaf;
    leaf.path = path;
    if (type == "string") {
      const std::uint32_t n = Uint32();
      const std::uint8_t* p = Take(n);
      leaf.kind = Leaf::kText;
      leaf.text.assign(reinterpret_cast<const char*>(p), n);
    } else if (type == "time" || type == "duration") {
      const std::int64_t sec = type == "time" ? static_cast<std::int64_t>(Get<std::uint32_t>())
                                              : static_cast<std::int64_t>(Get<std::int32_t>());
      const std::int64_t nsec = type == "time" ? static_cast<std::int64_t>(Get<std::uint32_t>())
                                               : static_cast<std::int64_t>(Get<std::int32_t>());
      leaf.ns = sec * 1'000'000'000 + nsec;
      leaf.number = static_cast<double>(sec) + 1e-9 * static_cast<double>(nsec);
    } else if (type == "bool" || type == "uint8" || type == "byte" || type == "char") {
      leaf.number = Get<std::uint8_t>();
    } else if (type == "int8") {
      leaf.number = Get<std::int8_t>();
    } else if (type == "int16") {
      leaf.number = Get<std::int16_t>();
    } else if (type == "uint16") {
      leaf.number = Get<std::uint16_t>();
    } else if (type == "int32") {
      leaf.number = Get<std::int32_t>();
    } else if (type == "uint32") {
      leaf.number = Get<std::uint32_t>();
    } else if (type == "int64") {
      leaf.number = static_cast<double>(Get<std::int64_t>());
    } else if (type == "uint64") {
      leaf.number = static_cast<double>(Get<std::uint64_t>());
    } else if (type == "float32") {
      leaf.number = Get<float>();
    } else {
      leaf.number = Get<double>();
    }
    visit_(leaf);
  }

  const MessageSpec& spec_;
  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t offset_ = 0;
  const std::function<void(const Leaf&)>& visit_;
};

}  // namespace

MessageSpec ParseDefinition(const std::string& root_type, std::string_view definition) {
  MessageSpec spec;
  spec.root = root_type;
  std::string current = root_type;
  std::vector<Field>* fields = &spec.types[current];
  text::LineCursor lines(definition);
  std::string_view raw;
  while (lines.Next(&raw)) {
    std::string_view line = raw.substr(0, std::min(raw.find('#'), raw.size()));
    line = text::Trim(line);
    if (line.empty()) continue;
    if (line.find_first_not_of('=') == std::string_view::npos) continue;  // section separator
    if (line.substr(0, 4) == "MSG:") {
      current = std::string(text::Trim(line.substr(4)));
      if (current.empty()) throw std::invalid_argument("ros1: an empty MSG: section name");
      fields = &spec.types[current];
      continue;
    }
    const std::size_t space = line.find_first_of(" \t");
    if (space == std::string_view::npos) {
      throw std::invalid_argument("ros1: " + current + ": cannot read the field '" +
                                  std::string(line) + "' (line " +
                                  std::to_string(lines.line_number()) + ")");
    }
    std::string type(line.substr(0, space));
    const std::string_view rest = text::Trim(line.substr(space));
    if (rest.find('=') != std::string_view::npos) continue;  // a constant
    Field field;
    field.name = std::string(rest);
    if (const std::size_t bracket = type.find('['); bracket != std::string::npos) {
      const std::string length = type.substr(bracket + 1, type.size() - bracket - 2);
      if (type.back() != ']') {
        throw std::invalid_argument("ros1: " + current + ": bad array type '" + type + "'");
      }
      field.is_array = true;
      if (!length.empty()) {
        const std::optional<std::uint64_t> n = text::ParseUint64(length);
        if (!n || *n > 1'000'000) {
          throw std::invalid_argument("ros1: " + current + ": bad array length '" + type + "'");
        }
        field.fixed_length = static_cast<int>(*n);
      }
      type = type.substr(0, bracket);
    }
    field.type = Resolve(type, PackageOf(current));
    fields->push_back(field);
  }
  // Every type used must be defined.
  for (const auto& [name, type_fields] : spec.types) {
    for (const Field& f : type_fields) {
      if (!IsPrimitive(f.type) && !spec.types.contains(f.type)) {
        throw std::invalid_argument("ros1: " + name + "." + f.name + ": no definition of " +
                                    f.type);
      }
    }
  }
  return spec;
}

void Decode(const MessageSpec& spec, const std::uint8_t* data, std::size_t size,
            const std::function<void(const Leaf&)>& visit) {
  Reader reader(spec, data, size, visit);
  reader.Message(spec.root, "", 0);
  reader.Finish();
}

std::map<std::string, Leaf> DecodeFields(const MessageSpec& spec, const std::uint8_t* data,
                                         std::size_t size, const std::vector<std::string>& paths) {
  const std::set<std::string> wanted(paths.begin(), paths.end());
  std::map<std::string, Leaf> found;
  Decode(spec, data, size, [&](const Leaf& leaf) {
    if (wanted.contains(leaf.path)) found[leaf.path] = leaf;
  });
  return found;
}

}  // namespace parkslam::io::ros1
