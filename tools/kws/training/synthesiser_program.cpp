#include "kws/training/synthesiser_program.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <stdexcept>

#include "devices/audio/sound_buffer.h"
#include "devices/audio/sound_file.h"
#include "kws/training/augment.h"

extern char** environ;

namespace marvin::perception::kws {

namespace {

// A pipe whose read end holds `input`, written and closed on our side before the program
// starts; both ends close on exec so that no other child inherits them.
struct InputPipe {
  int read_end = -1;
  explicit InputPipe(const std::string& program, const std::string& input) {
    if (input.size() > kMaxSynthesiserInput) {
      throw std::runtime_error(program + ": input of " + std::to_string(input.size()) +
                               " bytes, expected at most " + std::to_string(kMaxSynthesiserInput));
    }
    int fds[2];
    if (pipe2(fds, O_CLOEXEC) != 0)
      throw std::runtime_error(program + ": cannot make a pipe: " + std::strerror(errno));
    const ssize_t n = write(fds[1], input.data(), input.size());
    const int write_errno = errno;
    close(fds[1]);
    read_end = fds[0];
    if (n != static_cast<ssize_t>(input.size())) {
      close(read_end);
      throw std::runtime_error(program + ": cannot write its input: " + std::strerror(write_errno));
    }
  }
  ~InputPipe() { close(read_end); }
  InputPipe(const InputPipe&) = delete;
  InputPipe& operator=(const InputPipe&) = delete;
};

}  // namespace

std::vector<float> run_synthesiser(const std::vector<std::string>& argv, const std::string& role,
                                   const std::string& failure, const std::string& input) {
  const std::string& program = argv.at(0);
  const InputPipe stdin_pipe(program, input);
  // One temporary file per call: these programs write only to files or the sound device.
  static std::atomic<int> counter{0};
  const std::filesystem::path out = std::filesystem::temp_directory_path() /
                                    ("marvin-" + program + "-" + std::to_string(getpid()) + "-" +
                                     std::to_string(counter++) + ".wav");
  std::vector<std::string> args = argv;
  for (std::string& a : args)
    if (a == "{out}") a = out.string();
  std::vector<char*> c_args;
  for (std::string& a : args) c_args.push_back(a.data());
  c_args.push_back(nullptr);
  // Their chatter (festival warns about every missing diphone) would bury the trainer's
  // progress bar; failures are told by the exit status and the missing sound instead.
  posix_spawn_file_actions_t quiet;
  posix_spawn_file_actions_init(&quiet);
  posix_spawn_file_actions_adddup2(&quiet, stdin_pipe.read_end, STDIN_FILENO);
  posix_spawn_file_actions_addopen(&quiet, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_addopen(&quiet, STDERR_FILENO, "/dev/null", O_WRONLY, 0);
  pid_t pid = 0;
  const int err = posix_spawnp(&pid, program.c_str(), &quiet, nullptr, c_args.data(), environ);
  posix_spawn_file_actions_destroy(&quiet);
  if (err != 0) {
    throw std::runtime_error("cannot run " + program + " (" + role +
                             "; run scripts/setup): " + std::string(std::strerror(err)));
  }
  int status = 0;
  waitpid(pid, &status, 0);
  std::error_code ec;
  const bool wrote = std::filesystem::file_size(out, ec) > 44 && !ec;
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0 || !wrote) {
    std::filesystem::remove(out, ec);
    throw std::runtime_error(failure);
  }
  const std::vector<std::int16_t> pcm = audio::read_speech_file(out);
  std::filesystem::remove(out);
  return trim_silence(audio::to_float(pcm));
}

}  // namespace marvin::perception::kws
