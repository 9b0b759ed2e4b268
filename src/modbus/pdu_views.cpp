#include "modbus/pdu_views.hpp"

#include "core/byte_cursor.hpp"

namespace rtu {

// ---- FileRecordList ------------------------------------------------------------------

FileRecordList::Iterator::Iterator(std::span<const std::uint8_t> body, Layout layout,
                                   std::size_t pos)
    : body_(body), layout_(layout), pos_(pos) {
  if (pos_ >= body_.size()) {
    pos_ = body_.size() + 1;
    return;
  }
  parse();
}

void FileRecordList::Iterator::parse() {
  ByteCursor cur(body_.subspan(pos_));
  item_ = FileSubRecord{};
  if (layout_ == Layout::kReadResponse) {
    item_.resp_length = cur.u8();
    item_.ref_type = cur.u8();
    // resp_length counts the reference type byte and the data bytes.
    const std::size_t data = item_.resp_length > 0 ? item_.resp_length - 1U : 0U;
    item_.values = WordView(cur.take(data));
  } else {
    item_.ref_type = cur.u8();
    item_.file = cur.u16();
    item_.record = cur.u16();
    item_.record_length = cur.u16();
    if (layout_ == Layout::kWriteRequest) {
      item_.values = WordView(cur.take(std::size_t{item_.record_length} * 2U));
    }
  }
  item_.complete = cur.ok();
  next_ = pos_ + cur.position();
}

FileRecordList::Iterator& FileRecordList::Iterator::operator++() {
  if (!item_.complete || next_ >= body_.size()) {
    pos_ = body_.size() + 1;
    return *this;
  }
  pos_ = next_;
  parse();
  return *this;
}

std::size_t FileRecordList::count() const {
  std::size_t n = 0;
  for (auto it = begin(); it != end(); ++it) ++n;
  return n;
}

bool FileRecordList::well_formed() const {
  if (body_.empty()) return false;
  for (const auto& item : *this) {
    if (!item.complete) return false;
    // A read response item must hold at least its reference type and whole words.
    if (layout_ == Layout::kReadResponse &&
        (item.resp_length == 0 || (item.resp_length - 1U) % 2U != 0)) {
      return false;
    }
  }
  return true;
}

// ---- DeviceIdObjectList --------------------------------------------------------------

DeviceIdObjectList::Iterator::Iterator(std::span<const std::uint8_t> body, std::size_t remaining,
                                       std::size_t pos)
    : body_(body), remaining_(remaining), pos_(pos) {
  // An object needs at least its id and length bytes.
  if (remaining_ == 0 || pos_ + 2 > body_.size()) {
    pos_ = body_.size() + 1;
    return;
  }
  parse();
}

void DeviceIdObjectList::Iterator::parse() {
  ByteCursor cur(body_.subspan(pos_));
  item_.id = cur.u8();
  item_.length = cur.u8();
  item_.value = cur.take_up_to(item_.length);
  next_ = pos_ + cur.position();
}

DeviceIdObjectList::Iterator& DeviceIdObjectList::Iterator::operator++() {
  --remaining_;
  if (!item_.complete() || remaining_ == 0 || next_ + 2 > body_.size()) {
    pos_ = body_.size() + 1;
    return *this;
  }
  pos_ = next_;
  parse();
  return *this;
}

std::size_t DeviceIdObjectList::count() const {
  std::size_t n = 0;
  for (auto it = begin(); it != end(); ++it) ++n;
  return n;
}

std::size_t DeviceIdObjectList::used_bytes() const {
  std::size_t used = 0;
  std::size_t n = 0;
  for (const auto& object : *this) {
    used += 2U + object.value.size();
    ++n;
    if (!object.complete()) return body_.size();
  }
  return n == declared_ ? used : body_.size();
}

bool DeviceIdObjectList::complete() const {
  std::size_t n = 0;
  for (const auto& object : *this) {
    if (!object.complete()) return false;
    ++n;
  }
  return n == declared_;
}

}  // namespace rtu
