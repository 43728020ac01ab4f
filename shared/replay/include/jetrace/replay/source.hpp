// Where replay bytes come from: a file (checked to be a regular file of at
// most kMaxFileBytes before anything is read) or bytes in memory. Readers
// pull a record at a time, so memory stays bounded whatever the file's size.
#pragma once

#include <cstdint>
#include <cstdio>
#include <span>
#include <string>

namespace jetrace::replay {

class ByteSource {
public:
    virtual ~ByteSource() = default;
    /// Reads up to `n` bytes; fewer only at the end or on an error.
    virtual std::size_t read(std::uint8_t* dst, std::size_t n) = 0;
    /// The reason reading stopped early ("" at a clean end).
    virtual std::string error() const { return {}; }
};

class SpanSource final : public ByteSource {
public:
    explicit SpanSource(std::span<const std::uint8_t> bytes) : bytes_(bytes) {}
    std::size_t read(std::uint8_t* dst, std::size_t n) override;

private:
    std::span<const std::uint8_t> bytes_;
    std::size_t off_ = 0;
};

class FileSource final : public ByteSource {
public:
    FileSource() = default;
    ~FileSource() override;
    FileSource(const FileSource&) = delete;
    FileSource& operator=(const FileSource&) = delete;

    /// False with a message naming `path` if it is missing, not a regular
    /// file (a directory, a device, a pipe), larger than `max_bytes`, or
    /// cannot be opened.
    bool open(const std::string& path, std::string& error, std::uint64_t max_bytes);
    std::size_t read(std::uint8_t* dst, std::size_t n) override;
    std::string error() const override { return error_; }
    std::uint64_t size() const { return size_; }

private:
    std::FILE* file_ = nullptr;
    std::uint64_t size_ = 0;
    std::string error_;
};

}  // namespace jetrace::replay
