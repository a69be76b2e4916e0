//! LinuxCNC's rules of one word of each letter and one M code of each modal group in a block,
//! against what its own interpreter says of each case: Debian 12's `rs274` (linuxcnc-uspace
//! 2.9.0~pre1) on every letter written twice and every pair of the M codes it reads, recorded in
//! recordings/programs/linuxcnc/words/verdicts.tsv by make_verdicts.sh there.

use super::*;

const VERDICTS: &str = include_str!("../../recordings/programs/linuxcnc/words/verdicts.tsv");
const BLOCKS: &str = include_str!("../../recordings/programs/linuxcnc/words/blocks.tsv");

/// Where rs274 says "Multiple X words on one line" this reader refuses the word written twice, and
/// where it says "Two m codes used from same modal group" the second M code; where rs274 says
/// anything else or nothing, this reader names no two M codes of one group (it may refuse the block
/// for a code it does not read, as it refuses M62-M68).
#[test]
fn words_twice_and_m_codes_of_one_group_are_refused_where_linuxcnc_refuses_them() {
    let (mut twice, mut grouped, mut others) = (0, 0, 0);
    for row in VERDICTS.lines() {
        let (case, verdict) = row.split_once('\t').unwrap();
        let p = read_rs274(&format!("G21 G90\nT1 M6\n{case}\nM2\n"));
        let said: Vec<String> = errors(&p).into_iter().filter(|e| e.0 == 3).map(|e| e.2).collect();
        let grouped_said = said.iter().any(|m| m.contains("two M codes of modal group"));
        if verdict.starts_with("Multiple ") {
            let letter = case.split_whitespace().last().unwrap().chars().next().unwrap();
            assert!(said.iter().any(|m| m.contains(&format!("{letter} written twice in one block"))), "{case}: {said:?}");
            twice += 1;
        } else if verdict == "Two m codes used from same modal group" {
            assert!(grouped_said, "{case}: rs274 says {verdict}; here {said:?}");
            grouped += 1;
        } else {
            assert!(!grouped_said, "{case}: rs274 says {verdict}; here {said:?}");
            others += 1;
        }
    }
    // 19 letters, 115 pairs of one group (each code with itself among them), the rest of the 595 pairs.
    assert_eq!((twice, grouped, others), (19, 115, 480));
}

/// Blocks whose words alone LinuxCNC refuses (a G53 or a G52/G92 without axes, an arc code without R
/// I J K, a negative S, a T not a whole number of 0 or more, M61 without Q, a motion code beside a
/// group 0 code that takes the axes, G1-G3 without F in inverse time, G1 with no feed, an arc's
/// radius under 0.00005 in, M19's R, P or Q out of range, G86 after the tool change T1 M6 before
/// them, which stops the spindle, a tool the table does not list) and their neighbours it reads: refused here where rs274 refuses them, with its message quoted, and read
/// where it reads them.
#[test]
fn blocks_linuxcnc_refuses_for_their_words_alone_are_refused_and_their_neighbours_read() {
    // rs274's tool table (make_verdicts.sh): T1 alone, 10 mm.
    let options = ReadOptions { tool_table: Some(std::sync::Arc::new(fiveaxis::program::ToolTable::parse("T1 P1 Z0 D10 ;\n").unwrap())), ..Default::default() };
    let (mut refused, mut read_) = (0, 0);
    for row in BLOCKS.lines() {
        let (case, verdict) = row.split_once('\t').unwrap();
        let p = read(&format!("G21 G90\nT1 M6\n{case}\nM2\n"), Dialect::Rs274, "t.ngc", &options);
        let said: Vec<String> = errors(&p).into_iter().map(|e| format!("{}: {}", e.0, e.2)).collect();
        if verdict == "ok" {
            assert!(said.is_empty(), "{case}: rs274 reads it; here {said:?}");
            read_ += 1;
        } else {
            // Its message without the figures it adds after a colon ("Zero-radius arc: start=...").
            let message = verdict.split(':').next().unwrap();
            assert!(said.iter().any(|m| m.starts_with("3: ") && m.contains(&format!("\"{message}\""))), "{case}: rs274 says {verdict}; here {said:?}");
            refused += 1;
        }
    }
    assert_eq!((refused, read_), (32, 27));
}
