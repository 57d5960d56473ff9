use super::*;
use crate::description::Description;

const URDF: &str = r#"<robot name="r">
  <link name="l0"/><link name="l1"/><link name="l2"/><link name="hand"/>
  <joint name="j1" type="revolute"><parent link="l0"/><child link="l1"/><axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
  <joint name="j2" type="revolute"><parent link="l1"/><child link="l2"/><axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
  <joint name="j3" type="fixed"><parent link="l2"/><child link="hand"/></joint>
</robot>"#;

const SRDF: &str = r#"<?xml version="1.0"?>
<!-- a comment -->
<robot name="r">
  <group name="arm"><joint name="j1"/><joint name="j2"/></group>
  <group name="tool"><chain base_link="l0" tip_link="hand"/></group>
  <group name="both"><group name="arm"/><group name="tool"/></group>
  <group_state name="ready" group="arm">
    <joint name="j1" value="0.5"/>
    <joint name="j2" value="-0.25"/>
  </group_state>
  <end_effector name="ee" parent_link="hand" group="arm"/>
  <disable_collisions link1="l0" link2="l2" reason="Never"/>
</robot>"#;

#[test]
fn reads_groups_states_and_disabled_pairs() {
    let srdf = Srdf::parse(SRDF).expect("parses");
    assert_eq!(srdf.name, "r");
    assert_eq!(srdf.groups.len(), 3);
    assert_eq!(srdf.groups[0].joints, ["j1", "j2"]);
    assert_eq!(srdf.groups[2].subgroups, ["arm", "tool"]);
    let ready: Vec<_> = srdf.states_named("ready").collect();
    assert_eq!(ready[0].values, [("j1".into(), 0.5), ("j2".into(), -0.25)]);
    assert_eq!(ready[0].line, 7);
    assert_eq!(
        srdf.disabled_collisions,
        [DisabledPair {
            link1: "l0".into(),
            link2: "l2".into(),
            line: 12
        }]
    );
    let urdf = Description::parse(URDF).expect("urdf");
    assert!(srdf.problems(&urdf).is_empty());
    assert_eq!(
        srdf.group_chain("arm", &urdf),
        Ok(("l0".into(), "l2".into()))
    );
    assert_eq!(
        srdf.group_chain("tool", &urdf),
        Ok(("l0".into(), "hand".into()))
    );
    assert_eq!(
        srdf.group_chain("both", &urdf),
        Err(GroupChainError::NoChainOrJoints)
    );
    assert_eq!(srdf.group_chain("x", &urdf), Err(GroupChainError::Unknown));
}

#[test]
fn names_the_urdf_does_not_define_are_problems() {
    let srdf = Srdf::parse(
        r#"<robot name="r">
          <group name="arm"><joint name="j9"/></group>
          <group name="arm"><link name="l0"/></group>
          <group_state name="s" group="nope"><joint name="j1" value="0"/></group_state>
          <disable_collisions link1="l0" link2="ghost"/>
        </robot>"#,
    )
    .expect("parses");
    let urdf = Description::parse(URDF).expect("urdf");
    let problems: Vec<String> = srdf.problems(&urdf).iter().map(|p| p.to_string()).collect();
    assert_eq!(
        problems,
        [
            "line 2: `<group>` names joint `j9`, which the URDF does not define",
            "line 5: `<disable_collisions>` names link `ghost`, which the URDF does not define",
            "line 3: group `arm` is defined twice",
            "line 4: no group `nope` is defined",
        ]
    );
    assert_eq!(
        srdf.group_chain("arm", &urdf),
        Err(GroupChainError::NotASerialChain)
    );
}

#[test]
fn malformed_files_are_errors_with_lines_and_no_quotes() {
    let err = |text: &str| Srdf::parse(text).map(|_| ()).unwrap_err().to_string();
    assert_eq!(
        err("<robot>\n<group name='a'>\n</robot>"),
        "line 3: not well-formed XML"
    );
    assert_eq!(
        err("<config>secret</config>"),
        "its outermost element is not `<robot>`"
    );
    assert_eq!(err(""), "its outermost element is not `<robot>`");
    assert_eq!(
        err("<robot>\n<disable_collisions link1='a'/></robot>"),
        "line 2: `<disable_collisions>` has no `link2`"
    );
    assert_eq!(
        err("<robot><group_state name='s' group='g'><joint name='j' value='NaN'/></group_state></robot>"),
        "line 1: the value of joint `j` is not one finite number"
    );
    assert_eq!(
        err("<robot><chain base_link='a' tip_link='b'/></robot>"),
        "line 1: `<chain>` is not inside the element it belongs to"
    );
    // A DTD's entities are not expanded: the name that needs one is not read.
    let entity = Srdf::parse("<!DOCTYPE r [<!ENTITY e 'x'>]><robot name='&e;'/>");
    assert_eq!(entity.map(|s| s.name), Ok(String::new()));
}
