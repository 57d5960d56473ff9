//! Messy layouts become the canonical one: blank lines, quoting, empty cells, and the
//! `world` and `task` blocks.

use super::check;

#[test]
fn messy_layout_becomes_canonical() {
    let input = "cell   messy{units m,deg weights move 0.1,transition 2
workspace w1\"Left\"workspace    w2
  \"Right\" box center(0,0,0)size(1,1,1,)
adjacent w1 w2 fixed table reaches w1,w2, movable arm_1
reaches w2,
hand h{box size(1,2,3)at(0,0,1)rpy(90deg,0,0)sphere radius 2cm}
    robot r urdf \"r.urdf\" base b tip t arm a=r at(0,0,0)quat(1,0,0,0,)with h
surface s:k box center(0,0,0)size(1,1,0.1)reach height    5e-1 m
object o{shape cylinder radius 0.04height 0.2 symmetry about z order 4 grasp g1\"Top\"by arm_1 at(0,0,0.1)
rest r1 on table transition g1<->r1,o.g1, transition r1->g1}expect o:table in w1->arm_1.g1 in w2
expect w2 reached by at least 01 fixed expect no isolated states for o}";
    let expected = "cell messy {
  units m, deg
  weights move 0.1, transition 2
  workspace w1 \"Left\"
  workspace w2 \"Right\" box center (0, 0, 0) size (1, 1, 1)
  adjacent w1 w2
  fixed table reaches w1, w2
  movable arm_1 reaches w2
  hand h {
    box size (1, 2, 3) at (0, 0, 1) rpy (90 deg, 0, 0)
    sphere radius 2 cm
  }
  robot r urdf \"r.urdf\" base b tip t
  arm a = r at (0, 0, 0) quat (1, 0, 0, 0) with h
  surface s : k box center (0, 0, 0) size (1, 1, 0.1) reach height 5e-1 m
  object o {
    shape cylinder radius 0.04 height 0.2
    symmetry about z order 4
    grasp g1 \"Top\" by arm_1 at (0, 0, 0.1)
    rest r1 on table
    transition g1 <-> r1, o.g1
    transition r1 -> g1
  }
  expect o: table in w1 -> arm_1.g1 in w2
  expect w2 reached by at least 1 fixed
  expect no isolated states for o
}
";
    assert_eq!(check(input, "messy"), expected);
}

#[test]
fn blank_lines_collapse_to_one_and_never_touch_braces() {
    let input = "\n\ncell c {\n\n\n  units m\n\n\n\n  support s\n  support t\n\n  object o {\n\n    shape sphere radius 1\n\n\n    symmetry about x\n\n  }\n\n}\n\n";
    let expected = "cell c {\n  units m\n\n  support s\n  support t\n\n  object o {\n    shape sphere radius 1\n\n    symmetry about x\n  }\n}\n";
    assert_eq!(check(input, "blank lines"), expected);
}

#[test]
fn names_and_strings_are_quoted_and_escaped() {
    let input = "library `my lib` {\n  support `reach`\n  support `plain`\n  hand `two words` {}\n  include \"a \\\"b\\\" \\\\ c\\n\\td\"\n  object `o` { transition `a-b` <-> `o 2`.`c`, `object`.d }\n}\n";
    let expected = "library `my lib` {\n  support `reach`\n  support plain\n  hand `two words`\n  include \"a \\\"b\\\" \\\\ c\\n\\td\"\n  object o {\n    transition `a-b` <-> `o 2`.c, `object`.d\n  }\n}\n";
    assert_eq!(check(input, "names"), expected);
}

#[test]
fn empty_cell() {
    assert_eq!(check("cell   e {  }", "empty"), "cell e {}\n");
    assert_eq!(check("cell e {}\n// end\n", "empty"), "cell e {}\n// end\n");
}

#[test]
fn world_and_task_blocks_are_laid_out_one_line_each() {
    let input = "cell c {
world{cylinder :table at(0.45,0.45,1.0)  ball:left.top
  box : table.lying in w1}
  task   clear{cylinder   to bin in w2 ball to table at (1,2,3) rpy(0,0,90)}
  task empty {   }
}
";
    let expected = "cell c {
  world {
    cylinder: table at (0.45, 0.45, 1.0)
    ball: left.top
    box: table.lying in w1
  }
  task clear {
    cylinder to bin in w2
    ball to table at (1, 2, 3) rpy (0, 0, 90)
  }
  task empty {}
}
";
    assert_eq!(check(input, "world and task"), expected);
}

#[test]
fn comments_in_world_and_task_blocks_stay() {
    let input = "cell c {
  // the start
  world { // where things are
    // the cylinder first
    cylinder: table in w1 // on the left

    ball: /* held */ left.top
    // nothing else
  } // end of the world
  task t { /* one step */
    cylinder to /* the bin */ bin in w2 // away
  }
}
";
    let expected = "cell c {
  // the start
  world { // where things are
    // the cylinder first
    cylinder: table in w1 // on the left

    /* held */
    ball: left.top
    // nothing else
  } // end of the world
  task t { /* one step */
    /* the bin */
    cylinder to bin in w2 // away
  }
}
";
    assert_eq!(check(input, "world comments"), expected);
}
