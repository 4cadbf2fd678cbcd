#include "render/chunk.h"

#include "core/atomic_file.h"
#include "core/error.h"

#include <fmt/core.h>

#include <algorithm>
#include <charconv>
#include <cstring>
#include <fstream>
#include <sstream>

namespace sylva {

namespace {

constexpr char kPartialMagic[8] = {'S', 'Y', 'L', 'V', 'A', 'P', 'T', '1'};
constexpr uint64_t kMaxHeader = 1u << 20;

bool parse_int(const std::string& s, int& out) {
  const char* end = s.data() + s.size();
  const auto [ptr, ec] = std::from_chars(s.data(), end, out);
  return ec == std::errc() && ptr == end && !s.empty();
}

bool valid_name(const std::string& name) {
  return !name.empty() && std::all_of(name.begin(), name.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_';
  });
}

std::string header_text(const PartialHeader& h) {
  std::string text = "sylva partial render\n";
  auto line = [&](const std::string& name, const std::string& value) {
    if (value.find('\n') != std::string::npos) throw Error(fmt::format("partial header '{}' must be one line", name));
    text += name + "=" + value + "\n";
  };
  line("key", h.key);
  line("chunk", fmt::format("{}/{}", h.chunk.index, h.chunk.count));
  line("split", to_string(h.chunk.split));
  line("spp", std::to_string(h.spp));
  for (const auto& [name, value] : h.job) {
    if (!valid_name(name)) throw Error(fmt::format("partial header name '{}' is not [a-z0-9_]+", name));
    line("job." + name, value);
  }
  return text;
}

PartialHeader read_header(std::istream& in, const std::string& name) {
  char magic[sizeof(kPartialMagic)];
  in.read(magic, sizeof(magic));
  if (!in || std::memcmp(magic, kPartialMagic, sizeof(magic)) != 0)
    throw Error(name + ": not a Sylva partial render (written by sylva render --chunk)");
  uint64_t size = 0;
  in.read(reinterpret_cast<char*>(&size), sizeof(size));
  if (!in || size > kMaxHeader) throw Error(name + ": corrupt partial header");
  std::string text(size, '\0');
  in.read(text.data(), static_cast<std::streamsize>(size));
  if (!in) throw Error(name + ": truncated partial header");
  std::istringstream lines(text);
  std::string line;
  std::getline(lines, line);
  PartialHeader h;
  std::string chunk, split;
  bool has_key = false, has_spp = false;
  while (std::getline(lines, line)) {
    const size_t eq = line.find('=');
    if (eq == std::string::npos) throw Error(name + ": corrupt partial header line '" + line + "'");
    const std::string field = line.substr(0, eq), value = line.substr(eq + 1);
    if (field == "key") {
      h.key = value;
      has_key = true;
    } else if (field == "chunk") {
      chunk = value;
    } else if (field == "split") {
      split = value;
    } else if (field == "spp") {
      has_spp = parse_int(value, h.spp) && h.spp > 0;
    } else if (field.starts_with("job.")) {
      h.job[field.substr(4)] = value;
    } else {
      throw Error(name + ": unknown partial header field '" + field + "'");
    }
  }
  if (!has_key || !has_spp) throw Error(name + ": partial header lacks its key or spp");
  try {
    h.chunk = parse_chunk(chunk, split);
  } catch (const Error& e) {
    throw Error(name + ": corrupt partial header: " + e.what());
  }
  return h;
}

std::string list(const std::vector<int>& v) {
  std::string s;
  for (const int i : v) s += (s.empty() ? "" : ", ") + std::to_string(i);
  return s;
}

}  // namespace

ChunkSpec parse_chunk(const std::string& chunk, const std::string& split) {
  ChunkSpec spec;
  const size_t slash = chunk.find('/');
  if (slash == std::string::npos || !parse_int(chunk.substr(0, slash), spec.index) ||
      !parse_int(chunk.substr(slash + 1), spec.count) || spec.count < 1 || spec.index < 0 || spec.index >= spec.count)
    throw Error("chunk: expected i/N with 0 <= i < N, e.g. 0/4, not '" + chunk + "'");
  if (split == "samples")
    spec.split = ChunkSplit::samples;
  else if (split == "tiles")
    spec.split = ChunkSplit::tiles;
  else
    throw Error("split: expected 'samples' or 'tiles', not '" + split + "'");
  return spec;
}

std::string to_string(ChunkSplit split) { return split == ChunkSplit::samples ? "samples" : "tiles"; }

ChunkWork chunk_work(const ChunkSpec& spec, int width, int height, int spp) {
  const PixelRegion image = PixelRegion::whole(width, height);
  const SampleRange all{0, static_cast<uint32_t>(spp)};
  if (spec.split == ChunkSplit::samples) {
    if (spec.count > spp)
      throw Error(fmt::format("{} sample chunks of {} samples per pixel: every chunk needs a sample", spec.count, spp));
    return {image, sample_chunk(all, spec.index, spec.count)};
  }
  if (spec.count > height)
    throw Error(fmt::format("{} tile chunks of a {}-row image: every chunk needs a row", spec.count, height));
  return {row_chunk(image, spec.index, spec.count), all};
}

void save_partial(const std::filesystem::path& file, const PartialHeader& header, const Film& film) {
  const std::string text = header_text(header);
  write_file_atomic(file, [&](std::ostream& out) {
    out.write(kPartialMagic, sizeof(kPartialMagic));
    const uint64_t size = text.size();
    out.write(reinterpret_cast<const char*>(&size), sizeof(size));
    out.write(text.data(), static_cast<std::streamsize>(text.size()));
    film.write(out, header.key);
  });
}

PartialHeader load_partial_header(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw Error(file.string() + ": cannot open partial render");
  return read_header(in, file.string());
}

Partial load_partial(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw Error(file.string() + ": cannot open partial render");
  Partial p;
  p.file = file;
  p.header = read_header(in, file.string());
  p.film = Film::read(in, p.header.key, file.string());
  const ChunkWork work = chunk_work(p.header.chunk, p.film.width(), p.film.height(), p.header.spp);
  if (p.film.window() != work.region || p.film.first_sample() != work.samples.first)
    throw Error(file.string() + ": its film does not cover its chunk");
  return p;
}

ChunkAssembler::ChunkAssembler(int width, int height, int channels, int count)
    : count_(count), film_(width, height, channels), seen_(static_cast<size_t>(std::max(count, 0)), false) {
  if (count < 1) throw Error("a split render has at least one chunk");
}

void ChunkAssembler::add(int index, Film film) {
  if (index < 0 || index >= count_) throw Error(fmt::format("chunk {} of {} does not exist", index, count_));
  if (seen_[static_cast<size_t>(index)]) throw Error(fmt::format("chunk {} of {} arrived twice", index, count_));
  if (film.width() != film_.width() || film.height() != film_.height() || film.channels() != film_.channels())
    throw Error(fmt::format("chunk {} is a film of another image", index));
  seen_[static_cast<size_t>(index)] = true;
  waiting_.emplace(index, std::move(film));
  for (auto it = waiting_.find(next_); it != waiting_.end(); it = waiting_.find(next_)) {
    film_.merge(it->second);
    waiting_.erase(it);
    ++next_;
  }
}

const Film& ChunkAssembler::film() const {
  if (!complete()) throw Error(fmt::format("only {} of {} chunks are merged", next_, count_));
  return film_;
}

MergedParts merge_partials(const std::vector<std::filesystem::path>& files, bool allow_missing) {
  if (files.empty()) throw Error("no partial renders to merge");
  std::vector<PartialHeader> headers;
  for (const auto& f : files) headers.push_back(load_partial_header(f));
  const PartialHeader& first = headers.front();
  const int n = first.chunk.count;
  std::vector<int> owner(static_cast<size_t>(n), -1);  // index into files, per chunk
  for (size_t i = 0; i < files.size(); ++i) {
    const PartialHeader& h = headers[i];
    std::string differs;
    if (h.key != first.key)
      differs = "scene, seed, resolution, depth or bands";
    else if (h.spp != first.spp)
      differs = fmt::format("spp ({} vs {})", h.spp, first.spp);
    else if (h.chunk.count != n || h.chunk.split != first.chunk.split)
      differs = fmt::format("split ({}/{} by {} vs N = {} by {})", h.chunk.index, h.chunk.count,
                            to_string(h.chunk.split), n, to_string(first.chunk.split));
    else if (h.job != first.job)
      differs = "render options";
    if (!differs.empty())
      throw Error(
          fmt::format("{}: foreign part: its {} differ from {}'s", files[i].string(), differs, files.front().string()));
    int& slot = owner[static_cast<size_t>(h.chunk.index)];
    if (slot >= 0)
      throw Error(fmt::format("{}: duplicated part: chunk {}/{} is also {}", files[i].string(), h.chunk.index, n,
                              files[static_cast<size_t>(slot)].string()));
    slot = static_cast<int>(i);
  }
  MergedParts merged;
  merged.header = first;
  merged.header.chunk.index = 0;
  for (int c = 0; c < n; ++c)
    if (owner[static_cast<size_t>(c)] < 0) merged.missing.push_back(c);
  if (!merged.missing.empty() && !allow_missing)
    throw Error(
        fmt::format("missing chunks {} of {} (split by {})", list(merged.missing), n, to_string(first.chunk.split)));
  bool gap = false;
  for (int c = 0; c < n; ++c) {
    const int i = owner[static_cast<size_t>(c)];
    if (i < 0) {
      gap = true;
      continue;
    }
    if (gap && first.chunk.split == ChunkSplit::samples) {
      merged.unused.push_back(c);
      continue;
    }
    const Partial part = load_partial(files[static_cast<size_t>(i)]);
    if (part.header.key != first.key) throw Error(files[static_cast<size_t>(i)].string() + ": changed while merging");
    if (merged.film.channels() == 0) merged.film = Film(part.film.width(), part.film.height(), part.film.channels());
    merged.film.merge(part.film);
  }
  if (merged.film.channels() == 0) throw Error("no chunk could be merged (sample chunk 0 is missing)");
  return merged;
}

}  // namespace sylva
