// `slidespec analyze A B C` (or a glob): many records, each analysed as one record is, and
// one table of them all, as sweep has one of its runs.
#pragma once

#include <string>
#include <vector>

#include "slidespec/many_records.hpp"

namespace slidespec::cli {

/// Whether the records named are many: more than one, or a glob pattern (quoted, so the
/// shell left it), which may match any number.
bool many_records(const std::vector<std::string>& arguments);

/// The records named: each argument a file, or a glob pattern (*, ? or [ in a name that is
/// no file) expanded in name order. Throws InputError for a pattern that matches no file.
std::vector<std::string> expand_record_paths(const std::vector<std::string>& arguments);

/// Each record's output prefix: OUT_STEM (OUT_run1 for run1.csv). Throws InputError for
/// standard input among many, or two records of one stem (their outputs would collide).
std::vector<std::string> record_prefixes(const std::string& out, const std::vector<std::string>& records);

/// A record of many as the command lists it: its row and its own outputs' prefix (its
/// PREFIX.tsv/.json; "" when none were written).
struct ListedRecord {
  RecordRow row;
  std::string prefix;
};

/// All records in one TSV: '#' lines, a column line, one row per record (text columns:
/// file, segment, reason, the reason worded for the command line; a number not found is nan).
std::string records_table(const std::vector<ListedRecord>& rows, std::size_t named);
/// The same as JSON: {"records": [...], "named": N} (null for a number not found).
std::string records_json(const std::vector<ListedRecord>& rows, std::size_t named);

}  // namespace slidespec::cli
