#!/usr/bin/env bash
# readme_doc_test.sh README CAMBIO [--list]
#
# README.md, followed literally. Every ```sh / ```bash block of README runs, in the order it is
# written, from one scratch directory that holds firmware_config/ (this tree's) and
# build/bin/cambio (CAMBIO, the binary under test), so `build/bin/cambio ...` and `--out out/...`
# mean there what they mean at the project's root; a block runs under `bash -e -o pipefail` and
# must exit 0. What README shows a block printing is checked against what it prints now.
#
# README says what to do with a block in an HTML comment on the line just before its fence
# (invisible on the rendered page, there for whoever edits the README):
#
#   <!-- doc-test: skip (REASON) -->     the block does not run here; REASON is required (needs a
#                                        CAN kernel, root, a download, more than two minutes...)
#   <!-- doc-test: status N -->          the block runs and must exit N
#   <!-- doc-test: output of the block above[; numbers within P% or A][; stderr] -->
#                                        before a ```text block: the output of the nearest shell
#                                        block above it, which must have run. Its lines must
#                                        appear in that block's stdout (stderr with "; stderr"),
#                                        consecutively and from the first line to the last, with
#                                        runs of blanks counting as one and blank lines ignored.
#                                        A line that is only "..." stands for any number of lines
#                                        (so "..." first or last leaves the start or end open); a
#                                        line ending in " ..." must match the start of its line.
#                                        Numbers must be equal, or within P percent or A of the
#                                        README's when the marker says so: a figure may move a
#                                        little between machines, a stale one fails.
#
# Shell blocks without a marker run; other blocks without a marker (yaml, diagrams) are prose.
# A marker this script does not know fails the test, as does a skip without a reason.
#
# --list prints each block's line, language and what happens to it, and runs nothing.
# Environment: CAMBIO_DOC_TEST_TIMEOUT_S (per block, default 240); CAMBIO_DOC_TEST_KEEP=1 keeps
# the scratch directory (it is always kept when a block fails, and named).
set -uo pipefail

readme=${1:?usage: readme_doc_test.sh README CAMBIO [--list]}
cambio=${2:?usage: readme_doc_test.sh README CAMBIO [--list]}
list_only=0
[[ ${3:-} == --list ]] && list_only=1
timeout_s=${CAMBIO_DOC_TEST_TIMEOUT_S:-240}

say() { printf 'readme_doc_test: %s\n' "$*"; }

[[ -r ${readme} ]] || { say "cannot read ${readme}"; exit 2; }
if [[ ${list_only} == 0 ]]; then
  [[ -x ${cambio} ]] || { say "no executable ${cambio}"; exit 2; }
  cambio=$(cd -- "$(dirname -- "${cambio}")" && pwd -P)/$(basename -- "${cambio}")
fi
source_dir=$(cd -- "$(dirname -- "${readme}")" && pwd -P)
readme_name=$(basename -- "${readme}")

work=$(mktemp -d "${TMPDIR:-/tmp}/readme_doc_test.XXXXXX") || { say "cannot make a scratch directory"; exit 2; }
blocks=${work}/.blocks
scratch=${work}/root
mkdir -p -- "${blocks}" "${scratch}/build/bin"

# --- 1. Split README into blocks: blocks/N.txt (contents) and blocks/index (one per line:
# N <tab> fence line <tab> language <tab> marker text, "-" when none).
awk -v dir="${blocks}" '
  function flush_marker() { pending = "-" }
  BEGIN { n = 0; inside = 0; pending = "-"; previous_was_marker = 0 }
  {
    line = $0
    sub(/\r$/, "", line)
    if (!inside) {
      if (match(line, /^[ ]*```/)) {
        rest = substr(line, RSTART + RLENGTH)
        gsub(/[ \t]/, "", rest)
        lang = (rest == "") ? "-" : rest
        n++
        file = dir "/" n ".txt"
        printf "" > file
        marker = previous_was_marker ? pending : "-"
        printf "%d\t%d\t%s\t%s\n", n, NR, lang, marker > (dir "/index")
        inside = 1
        previous_was_marker = 0
        next
      }
      if (match(line, /^<!-- *doc-test:.*-->[ ]*$/)) {
        text = line
        sub(/^<!-- *doc-test: */, "", text)
        sub(/ *-->[ ]*$/, "", text)
        pending = text
        previous_was_marker = 1
        next
      }
      previous_was_marker = 0
      next
    }
    if (match(line, /^[ ]*```[ ]*$/)) { inside = 0; close(file); next }
    print line >> file
  }
  END { if (inside) { print "unterminated code fence" > "/dev/stderr"; exit 1 } }
' "${readme}" || { say "cannot parse ${readme}"; exit 2; }
touch -- "${blocks}/index"

# --- 2. Compare one expected text block with an actual output (see the header for the rules).
# Prints what did not match and exits 1, or exits 0.
compare_output() {  # compare_output EXPECTED ACTUAL REL_PERCENT ABS
  awk -v rel="$3" -v abs="$4" '
    function norm(s) {
      sub(/\r$/, "", s); gsub(/[ \t]+/, " ", s); sub(/^ /, "", s); sub(/ $/, "", s); return s
    }
    # Splits s into a skeleton (numbers replaced by #) and its numbers num[1..count].
    function split_numbers(s, num,    out, count, token) {
      out = ""; count = 0
      while (match(s, /-?[0-9]+(\.[0-9]+)?([eE][-+]?[0-9]+)?/)) {
        token = substr(s, RSTART, RLENGTH)
        # A "-" glued to a word (left_L0-2, x-1) is a hyphen, not a sign.
        if (substr(token, 1, 1) == "-" && RSTART > 1 && substr(s, RSTART - 1, 1) ~ /[A-Za-z0-9_]/) {
          out = out substr(s, 1, RSTART); s = substr(s, RSTART + 1); continue
        }
        out = out substr(s, 1, RSTART - 1) "#"
        num[++count] = token + 0
        s = substr(s, RSTART + RLENGTH)
      }
      split_count = count
      return out s
    }
    function close_enough(want, got,    d) {
      d = want - got; if (d < 0) d = -d
      if (d == 0) return 1
      w = want < 0 ? -want : want
      return d <= abs || d <= w * rel / 100
    }
    # Whether actual line a matches expected line e (e may end in " ...": a prefix).
    function line_matches(e, a,    prefix, es, as, en, an, ec, ac, i) {
      prefix = 0
      if (e ~ / \.\.\.$/) { prefix = 1; e = substr(e, 1, length(e) - 4) }
      es = split_numbers(e, en); ec = split_count
      as = split_numbers(a, an); ac = split_count
      if (prefix) {
        if (substr(as, 1, length(es)) != es) return 0
      } else if (as != es) return 0
      if (ac < ec) return 0
      for (i = 1; i <= ec; i++) if (!close_enough(en[i], an[i])) return 0
      return 1
    }
    # Whether expected lines from..to match actual lines starting at position at.
    function segment_at(from, to, at,    i) {
      if (at + (to - from) > na) return 0
      for (i = from; i <= to; i++) if (!line_matches(want[i], got[at + i - from])) return 0
      return 1
    }
    FNR == NR { s = norm($0); if (s != "") want[++ne] = s; next }
    { s = norm($0); if (s != "") got[++na] = s }
    END {
      # Segments of expected lines between "..." lines.
      nseg = 0; open_start = 0; open_end = 0; start = 0
      for (i = 1; i <= ne + 1; i++) {
        if (i > ne || want[i] == "...") {
          if (i <= ne && i == 1) open_start = 1
          if (i <= ne && i == ne) open_end = 1
          if (start) { seg_from[++nseg] = start; seg_to[nseg] = i - 1; start = 0 }
          continue
        }
        if (!start) start = i
      }
      at = 1
      for (k = 1; k <= nseg; k++) {
        found = 0
        anchored_start = (k == 1 && !open_start)
        anchored_end = (k == nseg && !open_end)
        if (anchored_end) {
          first = na - (seg_to[k] - seg_from[k])
          if (first >= at && (!anchored_start || first == 1) && segment_at(seg_from[k], seg_to[k], first)) {
            found = 1; at = na + 1
          }
        } else {
          for (p = at; p <= na; p++) {
            if (anchored_start && p > 1) break
            if (segment_at(seg_from[k], seg_to[k], p)) { found = 1; at = p + seg_to[k] - seg_from[k] + 1; break }
          }
        }
        if (!found) {
          # Name the first line of the segment that no placement matches in full.
          best = seg_from[k]; best_len = -1
          for (p = (anchored_start ? 1 : at); p <= na; p++) {
            for (i = seg_from[k]; i <= seg_to[k] && p + i - seg_from[k] <= na; i++)
              if (!line_matches(want[i], got[p + i - seg_from[k]])) break
            if (i - seg_from[k] > best_len) { best_len = i - seg_from[k]; best = i; best_at = p + i - seg_from[k] }
            if (anchored_start) break
          }
          if (best > seg_to[k]) {
            printf "  README line not matched: %s (it is not the output\x27s last line)\n", want[seg_to[k]]
            printf "  the output ends with:    %s\n", got[na]
          } else {
            printf "  README line not matched: %s\n", want[best]
            if (best_len >= 0 && best_at <= na) printf "  the output has there:    %s\n", got[best_at]
          }
          if (anchored_start && k == 1) printf "  (the block shows the output from its first line: start it with ... to leave it open)\n"
          if (anchored_end && k == nseg) printf "  (the block shows the output to its last line: end it with ... to leave it open)\n"
          exit 1
        }
      }
      if (nseg == 0) { printf "  the output block is empty\n"; exit 1 }
      exit 0
    }
  ' "$1" "$2"
}

# --- 3. Walk the blocks.
failures=0
ran=0
skipped=0
checked=0
last_shell=
last_shell_ran=0
fail() { say "FAILED: $*"; failures=$((failures + 1)); }

if [[ ${list_only} == 0 ]]; then
  ln -s -- "${source_dir}/firmware_config" "${scratch}/firmware_config"
  ln -s -- "${cambio}" "${scratch}/build/bin/cambio"
fi
started=$(date +%s)

while IFS=$'\t' read -r n line lang marker; do
  where="${readme_name}:${line}"
  case ${lang} in
    sh | bash | shell | console) kind=shell ;;
    *) kind=other ;;
  esac
  status_wanted=0
  action=
  if [[ ${marker} == - ]]; then
    [[ ${kind} == shell ]] && action=run || action=prose
  elif [[ ${marker} =~ ^skip\ *\((.+)\)$ ]]; then
    action=skip
    reason=${BASH_REMATCH[1]}
  elif [[ ${marker} =~ ^skip ]]; then
    fail "${where}: a skipped block needs a reason: <!-- doc-test: skip (why) -->"
    continue
  elif [[ ${marker} =~ ^status\ +([0-9]+)$ ]]; then
    action=run
    status_wanted=${BASH_REMATCH[1]}
  elif [[ ${marker} =~ ^output\ of\ the\ block\ above(.*)$ ]]; then
    action=output
    options=${BASH_REMATCH[1]}
  else
    fail "${where}: unknown doc-test marker '${marker}' (see tests/readme/readme_doc_test.sh)"
    continue
  fi
  if [[ ${action} == run || ${action} == skip ]] && [[ ${kind} != shell ]]; then
    fail "${where}: a '${marker}' marker on a ${lang} block: only sh and bash blocks run"
    continue
  fi

  case ${action} in
    prose) continue ;;
    skip)
      skipped=$((skipped + 1))
      last_shell=${n}
      last_shell_ran=0
      say "skip   ${where} (${reason})"
      ;;
    run)
      last_shell=${n}
      last_shell_ran=0
      if [[ ${list_only} == 1 ]]; then
        say "run    ${where}$([[ ${status_wanted} != 0 ]] && echo " (must exit ${status_wanted})")"
        continue
      fi
      ran=$((ran + 1))
      block_started=$(date +%s)
      (cd -- "${scratch}" && timeout --kill-after=10 "${timeout_s}" bash -e -o pipefail "${blocks}/${n}.txt") \
        >"${blocks}/${n}.stdout" 2>"${blocks}/${n}.stderr" </dev/null
      status=$?
      seconds=$(($(date +%s) - block_started))
      if [[ ${status} != "${status_wanted}" ]]; then
        fail "${where}: the block exited ${status} (README expects ${status_wanted}) after ${seconds} s$([[ ${status} == 124 ]] && echo ": timed out (CAMBIO_DOC_TEST_TIMEOUT_S=${timeout_s})")"
        sed 's/^/  | /' "${blocks}/${n}.txt"
        echo "  its stderr (last 15 lines):"
        tail -n 15 "${blocks}/${n}.stderr" | tr '\r' '\n' | tail -n 15 | sed 's/^/  > /'
        continue
      fi
      last_shell_ran=1
      say "ok     ${where} (exit ${status}, ${seconds} s)"
      ;;
    output)
      if [[ -z ${last_shell} ]]; then
        fail "${where}: 'output of the block above' but no shell block above it"
        continue
      fi
      rel=0
      abs=0
      stream=stdout
      rest=${options}
      while [[ -n ${rest} ]]; do
        if [[ ${rest} =~ ^\;\ *numbers\ within\ ([0-9.]+)%\ or\ ([0-9.]+)(.*)$ ]]; then
          rel=${BASH_REMATCH[1]}
          abs=${BASH_REMATCH[2]}
          rest=${BASH_REMATCH[3]}
        elif [[ ${rest} =~ ^\;\ *stderr(.*)$ ]]; then
          stream=stderr
          rest=${BASH_REMATCH[1]}
        else
          fail "${where}: cannot read '${rest}' in the output marker (options: '; numbers within P% or A', '; stderr')"
          continue 2
        fi
      done
      tolerance="numbers within ${rel}% or ${abs}"
      [[ ${rel} == 0 && ${abs} == 0 ]] && tolerance="numbers exact"
      if [[ ${list_only} == 1 ]]; then
        say "check  ${where} against the ${stream} of the block above (${tolerance})"
        continue
      fi
      if ! grep -q '[^[:space:]]' "${blocks}/${n}.txt"; then
        fail "${where}: the output block is empty"
        continue
      fi
      if [[ ${last_shell_ran} != 1 ]]; then
        fail "${where}: the block above did not run (skipped or failed): its output cannot be checked"
        continue
      fi
      checked=$((checked + 1))
      if compare_output "${blocks}/${n}.txt" "${blocks}/${last_shell}.${stream}" "${rel}" "${abs}" \
        >"${blocks}/${n}.diff"; then
        say "ok     ${where} (the output shown is what the block prints)"
      else
        fail "${where}: the output shown is not what the block above prints now"
        cat "${blocks}/${n}.diff"
        echo "  the block's ${stream} now:"
        tr '\r' '\n' <"${blocks}/${last_shell}.${stream}" | head -n 60 | sed 's/^/  > /'
      fi
      ;;
  esac
done <"${blocks}/index"

if [[ ${list_only} == 1 ]]; then
  rm -rf -- "${work}"
  exit $((failures > 0))
fi
elapsed=$(($(date +%s) - started))
if [[ ${ran} == 0 ]]; then
  fail "no block of ${readme} ran"
fi
if [[ ${failures} -gt 0 ]]; then
  say "${failures} problem(s) in ${readme}: ${ran} blocks run, ${skipped} skipped, ${checked} outputs checked, ${elapsed} s; scratch directory kept: ${scratch}"
  exit 1
fi
say "${readme_name} holds: ${ran} blocks run, ${skipped} skipped (each says why), ${checked} outputs checked, ${elapsed} s"
if [[ ${CAMBIO_DOC_TEST_KEEP:-0} == 1 ]]; then
  say "scratch directory kept: ${scratch}"
else
  rm -rf -- "${work}"
fi
exit 0
