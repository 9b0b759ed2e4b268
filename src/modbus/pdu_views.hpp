#pragma once
// Non-owning views over the variable parts of a Modbus PDU: register words, packed bits,
// file-record sub-requests and device-identification objects. They point into a Record's
// bytes (valid as long as that Record), never allocate, and never read past their span:
// a list whose declared lengths run past the end yields only what is present.
#include <cstddef>
#include <cstdint>
#include <iterator>
#include <span>

namespace rtu {

// 16-bit big-endian words (MODBUS Application Protocol V1.1b3 §4.2). An odd trailing byte
// is not a word and is not shown here.
class WordView {
 public:
  constexpr WordView() = default;
  constexpr explicit WordView(std::span<const std::uint8_t> bytes) : bytes_(bytes) {}

  [[nodiscard]] constexpr std::size_t size() const { return bytes_.size() / 2; }
  [[nodiscard]] constexpr bool empty() const { return size() == 0; }
  // Precondition: i < size().
  [[nodiscard]] constexpr std::uint16_t operator[](std::size_t i) const {
    return static_cast<std::uint16_t>((unsigned{bytes_[2 * i]} << 8U) |
                                      unsigned{bytes_[2 * i + 1]});
  }
  [[nodiscard]] constexpr std::span<const std::uint8_t> bytes() const { return bytes_; }

 private:
  std::span<const std::uint8_t> bytes_;
};

// Bits packed LSB first: bit k is bit (k % 8) of byte k / 8 (V1.1b3 §6.1, §6.11).
class BitView {
 public:
  constexpr BitView() = default;
  // `count` is clamped to the bits the bytes hold.
  constexpr BitView(std::span<const std::uint8_t> bytes, std::size_t count)
      : bytes_(bytes), count_(count < bytes.size() * 8 ? count : bytes.size() * 8) {}

  [[nodiscard]] constexpr std::size_t size() const { return count_; }
  [[nodiscard]] constexpr bool empty() const { return count_ == 0; }
  // Precondition: i < size().
  [[nodiscard]] constexpr bool operator[](std::size_t i) const {
    return ((unsigned{bytes_[i / 8]} >> (i % 8)) & 1U) != 0;
  }
  [[nodiscard]] constexpr std::span<const std::uint8_t> bytes() const { return bytes_; }

 private:
  std::span<const std::uint8_t> bytes_;
  std::size_t count_ = 0;
};

// One item of FC20 / FC21 (V1.1b3 §6.14, §6.15).
struct FileSubRecord {
  std::uint8_t ref_type = 0;        // must be 6
  std::uint16_t file = 0;           // requests only
  std::uint16_t record = 0;         // requests only
  std::uint16_t record_length = 0;  // requests only: length in 16-bit words
  std::uint8_t resp_length = 0;     // FC20 responses only: bytes after this one (ref + data)
  WordView values;                  // FC21 both roles, FC20 responses; clipped to the frame
  bool complete = true;             // false when the frame ends inside this item
};

// Walks the items of a file-record PDU body (after its byte count).
class FileRecordList {
 public:
  enum class Layout : std::uint8_t {
    kReadRequest,   // FC20 request: 7-byte sub-requests
    kWriteRequest,  // FC21 request and its echo: 7 bytes + record_length words each
    kReadResponse,  // FC20 response: resp_length, ref_type, data
  };

  class Iterator {
   public:
    using iterator_category = std::forward_iterator_tag;
    using value_type = FileSubRecord;
    using difference_type = std::ptrdiff_t;
    using pointer = const FileSubRecord*;
    using reference = const FileSubRecord&;

    Iterator() = default;
    Iterator(std::span<const std::uint8_t> body, Layout layout, std::size_t pos);
    reference operator*() const { return item_; }
    pointer operator->() const { return &item_; }
    Iterator& operator++();
    Iterator operator++(int) {
      Iterator old = *this;
      ++*this;
      return old;
    }
    friend bool operator==(const Iterator& a, const Iterator& b) { return a.pos_ == b.pos_; }

   private:
    void parse();
    std::span<const std::uint8_t> body_;
    Layout layout_ = Layout::kReadRequest;
    std::size_t pos_ = 0;   // start of the current item; body_.size() + 1 = end
    std::size_t next_ = 0;  // start of the next item
    FileSubRecord item_;
  };

  FileRecordList() = default;
  FileRecordList(std::span<const std::uint8_t> body, Layout layout)
      : body_(body), layout_(layout) {}

  [[nodiscard]] Iterator begin() const { return {body_, layout_, 0}; }
  [[nodiscard]] Iterator end() const { return {body_, layout_, body_.size() + 1}; }
  [[nodiscard]] std::size_t count() const;
  // True when the items exactly fill the body, with no partial item at the end.
  [[nodiscard]] bool well_formed() const;
  [[nodiscard]] Layout layout() const { return layout_; }
  [[nodiscard]] std::span<const std::uint8_t> body() const { return body_; }

 private:
  std::span<const std::uint8_t> body_;
  Layout layout_ = Layout::kReadRequest;
};

// One object of an FC43 / MEI 0E response: id, length, value (V1.1b3 §6.21).
struct DeviceIdObject {
  std::uint8_t id = 0;
  std::uint8_t length = 0;              // as declared
  std::span<const std::uint8_t> value;  // clipped to the frame
  [[nodiscard]] bool complete() const { return value.size() == length; }
};

// Walks at most `declared` objects; stops early when the bytes run out.
class DeviceIdObjectList {
 public:
  class Iterator {
   public:
    using iterator_category = std::forward_iterator_tag;
    using value_type = DeviceIdObject;
    using difference_type = std::ptrdiff_t;
    using pointer = const DeviceIdObject*;
    using reference = const DeviceIdObject&;

    Iterator() = default;
    Iterator(std::span<const std::uint8_t> body, std::size_t remaining, std::size_t pos);
    reference operator*() const { return item_; }
    pointer operator->() const { return &item_; }
    Iterator& operator++();
    Iterator operator++(int) {
      Iterator old = *this;
      ++*this;
      return old;
    }
    friend bool operator==(const Iterator& a, const Iterator& b) { return a.pos_ == b.pos_; }

   private:
    void parse();
    std::span<const std::uint8_t> body_;
    std::size_t remaining_ = 0;  // objects still to read, this one included
    std::size_t pos_ = 0;        // body_.size() + 1 = end
    std::size_t next_ = 0;
    DeviceIdObject item_;
  };

  DeviceIdObjectList() = default;
  DeviceIdObjectList(std::span<const std::uint8_t> body, std::size_t declared)
      : body_(body), declared_(declared) {}

  [[nodiscard]] Iterator begin() const { return {body_, declared_, 0}; }
  [[nodiscard]] Iterator end() const { return {body_, 0, body_.size() + 1}; }
  [[nodiscard]] std::size_t count() const;
  // Bytes the declared objects occupy when they fit; the body size when they do not.
  [[nodiscard]] std::size_t used_bytes() const;
  // True when every declared object is present in full.
  [[nodiscard]] bool complete() const;
  [[nodiscard]] std::size_t declared() const { return declared_; }

 private:
  std::span<const std::uint8_t> body_;
  std::size_t declared_ = 0;
};

}  // namespace rtu
