// The intruder photos on the Events page (API.md: GET /api/events/ID/photo). The guard
// logs "Intruder alert: ... Photo: <path>" (app/host.cpp); the page asks by the event's id,
// never by a path, and only a JPEG file inside the photo folder (<data dir>/photos, where
// the host's camera saves them) is served: the file the event names is opened without
// following a final link, and the path the kernel opened (/proc/self/fd) must lie inside the
// resolved folder, so an event or a link that points elsewhere serves nothing, even one
// swapped in while the request runs.
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <filesystem>

#include "data/sqlite_store.h"
#include "web/api.h"

namespace marvin::web {

namespace fs = std::filesystem;

namespace {

struct FileCloser {
  int fd;
  ~FileCloser() { ::close(fd); }
};

}  // namespace

std::string photo_of_event(const std::string& kind, const std::string& message) {
  static constexpr std::string_view kMark = " Photo: ";
  if (kind != "intruder") return {};
  const std::size_t at = message.rfind(kMark);
  return at == std::string::npos ? std::string() : message.substr(at + kMark.size());
}

fs::path Api::photos_dir() const {
  return options_.photos_dir.empty() ? store_.path().parent_path() / "photos"
                                     : options_.photos_dir;
}

ApiResponse Api::event_photo(const std::string& id_text) {
  const std::int64_t id = parse_id(id_text, "event");
  const std::optional<data::Event> event = store_.event(id);
  if (!event) throw ApiError(404, "no event with id " + std::to_string(id));
  const std::string named = photo_of_event(event->kind, event->message);
  if (named.empty()) throw ApiError(404, "event " + std::to_string(id) + " has no photo");
  // Messages never echo the path back: it would tell a visitor where the data lives.
  const std::string refused = "event " + std::to_string(id) +
                              ": its photo is not in Marvin's photo folder; nothing is served";
  std::error_code ec;
  const fs::path folder = fs::canonical(photos_dir(), ec);
  if (ec) throw ApiError(404, "event " + std::to_string(id) + ": no photo folder here");
  // Open first, then check what was opened (its path as the kernel resolved it, and its
  // type), then read from that same descriptor: a file swapped for a link between a check
  // and the open cannot send anything outside the folder.
  const int fd = ::open(named.c_str(), O_RDONLY | O_CLOEXEC | O_NOFOLLOW | O_NONBLOCK);
  if (fd < 0) {
    if (errno == ENOENT || errno == ENOTDIR) {
      throw ApiError(404, "event " + std::to_string(id) + ": its photo is gone");
    }
    throw ApiError(403, refused);  // ELOOP: the photo itself is a link
  }
  const FileCloser closer{fd};
  const fs::path file = fs::read_symlink("/proc/self/fd/" + std::to_string(fd), ec);
  if (ec) throw ApiError(403, refused);
  const fs::path inside = file.lexically_relative(folder);
  if (inside.empty() || *inside.begin() == ".." || inside.is_absolute())
    throw ApiError(403, refused);
  struct stat info {};
  if (::fstat(fd, &info) != 0 || !S_ISREG(info.st_mode) || file.extension() != ".jpg")
    throw ApiError(403, refused);
  std::string bytes(static_cast<std::size_t>(info.st_size), '\0');
  std::size_t got = 0;
  while (got < bytes.size()) {
    const ssize_t n = ::read(fd, bytes.data() + got, bytes.size() - got);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    got += static_cast<std::size_t>(n);
  }
  bytes.resize(got);
  // A JPEG starts with FF D8 FF: anything else in the folder is not served as a photo.
  if (bytes.size() < 3 || static_cast<unsigned char>(bytes[0]) != 0xFF ||
      static_cast<unsigned char>(bytes[1]) != 0xD8 || static_cast<unsigned char>(bytes[2]) != 0xFF)
    throw ApiError(403, refused);
  ApiResponse out;
  out.content_type = "image/jpeg";
  out.raw = std::move(bytes);
  return out;
}

}  // namespace marvin::web
