//! Value shapes: which aggregates are robtargets, jointtargets, tooldata
//! or wobjdata, and their numbers.

use super::*;

pub(super) const ROBTARGET_FORM: &str =
    "a robtarget is [[x,y,z],[q1,q2,q3,q4],[cf1,cf4,cf6,cfx],[eax_a,eax_b,eax_c,eax_d,eax_e,eax_f]]";
pub(super) const JOINTTARGET_FORM: &str =
    "a jointtarget is [[rax_1,rax_2,rax_3,rax_4,rax_5,rax_6],[eax_a,eax_b,eax_c,eax_d,eax_e,eax_f]]";

pub(super) fn num(e: &Expr) -> Option<Number> {
    match e {
        Expr::Num(n) => Some(n.clone()),
        _ => None,
    }
}

pub(super) fn nums<const N: usize>(e: &Expr) -> Option<[Number; N]> {
    let items = aggregate(e, N)?;
    let v: Vec<Number> = items.iter().map(num).collect::<Option<_>>()?;
    v.try_into().ok()
}

pub(super) fn aggregate(e: &Expr, n: usize) -> Option<&[Expr]> {
    match e {
        Expr::Aggregate(a) if a.items.len() == n => Some(&a.items),
        _ => None,
    }
}

pub(super) fn flag(e: &Expr) -> Option<Flag> {
    match e {
        Expr::Bool(b) => Some(Flag {
            value: *b,
            span: 0..0,
        }),
        _ => None,
    }
}

/// `Ok(Some)` for a literal robtarget, `Ok(None)` for the right shape with
/// components that are expressions, `Err(why)` for a wrong shape.
pub(super) fn robtarget_shape(
    items: &[Expr],
) -> std::result::Result<Option<RobTargetValue>, String> {
    const SIZES: [usize; 4] = [3, 4, 4, 6];
    const NAMES: [&str; 4] = ["position", "orientation", "robconf", "extax"];
    if items.len() != 4 {
        return Err(format!("{} parts instead of 4", items.len()));
    }
    let mut all_literal = true;
    for (i, it) in items.iter().enumerate() {
        match it {
            Expr::Aggregate(a) => {
                let sub = &a.items;
                if sub.len() != SIZES[i] {
                    return Err(format!(
                        "{} has {} numbers instead of {}",
                        NAMES[i],
                        sub.len(),
                        SIZES[i]
                    ));
                }
                all_literal &= sub.iter().all(|x| matches!(x, Expr::Num(_)));
            }
            _ => all_literal = false,
        }
    }
    if !all_literal {
        // Components given by expressions or whole parts by name: valid
        // RAPID, but not numbers this tool can rewrite.
        let parts_ok = items
            .iter()
            .all(|x| !matches!(x, Expr::Str(_) | Expr::Bool(_)));
        return if parts_ok {
            Ok(None)
        } else {
            Err("a part is not numeric".into())
        };
    }
    Ok(Some(RobTargetValue {
        trans: nums::<3>(&items[0]).ok_or("position")?,
        rot: nums::<4>(&items[1]).ok_or("orientation")?,
        robconf: nums::<4>(&items[2]).ok_or("robconf")?,
        extax: nums::<6>(&items[3]).ok_or("extax")?,
    }))
}

type JointValue = ([Number; 6], [Number; 6]);

pub(super) fn jointtarget_shape(items: &[Expr]) -> std::result::Result<Option<JointValue>, String> {
    if items.len() != 2 {
        return Err(format!("{} parts instead of 2", items.len()));
    }
    for (i, it) in items.iter().enumerate() {
        if let Expr::Aggregate(a) = it {
            let sub = &a.items;
            if sub.len() != 6 {
                let what = if i == 0 { "robax" } else { "extax" };
                return Err(format!("{what} has {} numbers instead of 6", sub.len()));
            }
        }
    }
    match (nums::<6>(&items[0]), nums::<6>(&items[1])) {
        (Some(a), Some(b)) => Ok(Some((a, b))),
        _ => Ok(None),
    }
}

pub(super) fn tooldata(
    e: &Expr,
    name: String,
    origin: Origin,
    storage: Storage,
) -> Option<ToolData> {
    let items = aggregate(e, 3)?;
    let robhold = flag(&items[0])?;
    let tframe = aggregate(&items[1], 2)?;
    let load = aggregate(&items[2], 6)?;
    let inertia: Vec<Number> = load[3..].iter().map(num).collect::<Option<_>>()?;
    Some(ToolData {
        name,
        origin,
        storage,
        robhold,
        tframe_trans: nums::<3>(&tframe[0])?,
        tframe_rot: nums::<4>(&tframe[1])?,
        mass: num(&load[0])?,
        cog: nums::<3>(&load[1])?,
        aom: nums::<4>(&load[2])?,
        inertia: inertia.try_into().ok()?,
    })
}

pub(super) fn wobjdata(
    e: &Expr,
    name: String,
    origin: Origin,
    storage: Storage,
) -> Option<WobjData> {
    let items = aggregate(e, 5)?;
    let ufmec = match &items[2] {
        Expr::Str(s) => s.to_string(),
        _ => return None,
    };
    let uf = aggregate(&items[3], 2)?;
    let of = aggregate(&items[4], 2)?;
    Some(WobjData {
        name,
        origin,
        storage,
        robhold: flag(&items[0])?,
        ufprog: flag(&items[1])?,
        ufmec,
        uframe_trans: nums::<3>(&uf[0])?,
        uframe_rot: nums::<4>(&uf[1])?,
        oframe_trans: nums::<3>(&of[0])?,
        oframe_rot: nums::<4>(&of[1])?,
    })
}
