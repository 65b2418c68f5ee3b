//! C's `printf` formats for `CPPMethods::printf`: `%d %i %u %x %X %o %c %s %f %e %g %%` with
//! the flags `-`, `0`, `+` and space, a width and a precision (`*` is not supported).

use super::value::Value;

/// `format` with `args` substituted, as C's `printf` writes it.
pub fn format(format: &str, args: &[Value]) -> Result<String, String> {
    let mut out = String::new();
    let mut args = args.iter();
    let mut chars = format.chars().peekable();
    while let Some(c) = chars.next() {
        if c != '%' {
            out.push(c);
            continue;
        }
        let mut flags = String::new();
        while let Some(&f) = chars.peek().filter(|f| "-0+ #".contains(**f)) {
            flags.push(f);
            chars.next();
        }
        let mut width = String::new();
        while let Some(&d) = chars.peek().filter(|d| d.is_ascii_digit()) {
            width.push(d);
            chars.next();
        }
        let mut precision = None;
        if chars.peek() == Some(&'.') {
            chars.next();
            let mut digits = String::new();
            while let Some(&d) = chars.peek().filter(|d| d.is_ascii_digit()) {
                digits.push(d);
                chars.next();
            }
            precision = Some(digits.parse::<usize>().unwrap_or(0));
        }
        // Length modifiers change nothing here.
        while chars.peek().is_some_and(|l| "hlLqjzt".contains(*l)) {
            chars.next();
        }
        let Some(conversion) = chars.next() else { return Err("the format ends in `%`".into()) };
        if conversion == '%' {
            out.push('%');
            continue;
        }
        let arg = args.next().ok_or_else(|| format!("`%{conversion}` has no argument"))?;
        let number = arg.number();
        let body = match (conversion, number) {
            ('d' | 'i', Some(n)) => signed(n.as_i64() as i32 as i64, &flags),
            ('u', Some(n)) => (n.as_i64() as u32).to_string(),
            ('x', Some(n)) => format!("{:x}", n.as_i64() as u32),
            ('X', Some(n)) => format!("{:X}", n.as_i64() as u32),
            ('o', Some(n)) => format!("{:o}", n.as_i64() as u32),
            ('c', Some(n)) => char::from(n.as_i64() as u8).to_string(),
            ('f' | 'F', Some(n)) => sign(format!("{:.*}", precision.unwrap_or(6), n.as_f64()), &flags),
            ('e' | 'E', Some(n)) => {
                let text = exponent(n.as_f64(), precision.unwrap_or(6));
                sign(if conversion == 'E' { text.to_uppercase() } else { text }, &flags)
            }
            ('g' | 'G', Some(n)) => sign(format!("{}", n.as_f64()), &flags),
            ('s', _) => match arg {
                Value::Str(s) => match precision {
                    Some(p) => s.chars().take(p).collect(),
                    None => s.to_string(),
                },
                other => return Err(format!("`%s` is given a {}", other.kind())),
            },
            (c, None) => return Err(format!("`%{c}` is given a {}", arg.kind())),
            (c, Some(_)) => return Err(format!("`%{c}` is not a conversion printf knows")),
        };
        let width: usize = width.parse().unwrap_or(0);
        let pad = width.saturating_sub(body.chars().count());
        if flags.contains('-') {
            out.push_str(&body);
            out.extend(std::iter::repeat_n(' ', pad));
        } else if flags.contains('0') && conversion != 's' {
            let (sign, digits) = body.split_at(body.starts_with(['-', '+', ' ']) as usize);
            out.push_str(sign);
            out.extend(std::iter::repeat_n('0', pad));
            out.push_str(digits);
        } else {
            out.extend(std::iter::repeat_n(' ', pad));
            out.push_str(&body);
        }
    }
    Ok(out)
}

fn signed(n: i64, flags: &str) -> String {
    sign(n.to_string(), flags)
}

/// `+` or space before a non-negative number, when the flags ask.
fn sign(text: String, flags: &str) -> String {
    match (text.starts_with('-'), flags.contains('+'), flags.contains(' ')) {
        (false, true, _) => format!("+{text}"),
        (false, false, true) => format!(" {text}"),
        _ => text,
    }
}

/// `1.500000e+02`, as C writes `%e`.
fn exponent(value: f64, precision: usize) -> String {
    let text = format!("{value:.precision$e}");
    match text.split_once('e') {
        Some((mantissa, exp)) => {
            let exp: i32 = exp.parse().unwrap_or(0);
            format!("{mantissa}e{}{:02}", if exp < 0 { '-' } else { '+' }, exp.abs())
        }
        None => text,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn formats_as_c_does() {
        let args = [Value::UInt(4711), Value::Int(-42), Value::Float(3.25), Value::Str("ab".into())];
        assert_eq!(format("v %u i %d f %.2f s %s %%", &args).unwrap(), "v 4711 i -42 f 3.25 s ab %");
        assert_eq!(
            format("[%5d|%-5d|%05d]", &[Value::Int(42), Value::Int(42), Value::Int(-42)]).unwrap(),
            "[   42|42   |-0042]"
        );
        assert_eq!(format("%e %x", &[Value::Float(150.0), Value::Int(255)]).unwrap(), "1.500000e+02 ff");
        assert!(format("%d", &[]).unwrap_err().contains("no argument"));
        assert!(format("%s", &[Value::Int(1)]).unwrap_err().contains("given a int"));
    }
}
