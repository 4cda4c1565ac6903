#include "model/table/table_result.hpp"

namespace dxlemu::model {

wire::StatusError v2_status_error(TableError error) {
  switch (error) {
    case TableError::None:
      return wire::StatusError::None;
    case TableError::Access:
    case TableError::Locked:
      return wire::StatusError::Access;
    case TableError::DataLength:
      return wire::StatusError::DataLength;
    case TableError::DataRange:
      return wire::StatusError::DataRange;
    case TableError::DataLimit:
    case TableError::AngleLimit:
      return wire::StatusError::DataLimit;
    case TableError::ResultFail:
      return wire::StatusError::ResultFail;
  }
  return wire::StatusError::ResultFail;
}

std::uint8_t v1_error_bits(TableError error) {
  switch (error) {
    case TableError::None:
      return 0;
    case TableError::AngleLimit:
      return wire::v1_error::kAngleLimit;
    case TableError::Access:
    case TableError::Locked:
    case TableError::DataLength:
    case TableError::DataRange:
    case TableError::DataLimit:
    case TableError::ResultFail:
      // "Range Error: When an instruction is out of the range for use" (protocol1.md "Error").
      return wire::v1_error::kRange;
  }
  return wire::v1_error::kRange;
}

wire::Outcome outcome_of(TableError error) {
  switch (error) {
    case TableError::None:
      return wire::Outcome::Ok;
    case TableError::Access:
      return wire::Outcome::Access;
    case TableError::Locked:
      return wire::Outcome::Locked;
    case TableError::DataLength:
      return wire::Outcome::DataLength;
    case TableError::DataRange:
      return wire::Outcome::DataRange;
    case TableError::DataLimit:
      return wire::Outcome::DataLimit;
    case TableError::AngleLimit:
      return wire::Outcome::AngleLimit;
    case TableError::ResultFail:
      return wire::Outcome::ResultFail;
  }
  return wire::Outcome::ResultFail;
}

}  // namespace dxlemu::model
