//! The self-contained HTML page: tables, inline SVG plots, the command and
//! version that made it. Everything that comes from a file is escaped.

/// Escapes text for HTML content and attribute values.
pub fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&#39;"),
            c => out.push(c),
        }
    }
    out
}

/// A page under construction.
#[derive(Debug, Default)]
pub struct Page {
    title: String,
    body: String,
    surfaces: usize,
}

impl Page {
    /// A page with this title.
    pub fn new(title: &str) -> Page {
        Page {
            title: title.to_string(),
            body: String::new(),
            surfaces: 0,
        }
    }

    /// A section heading.
    pub fn heading(&mut self, text: &str) {
        self.body.push_str(&format!("<h2>{}</h2>\n", escape(text)));
    }

    /// A paragraph of text.
    pub fn paragraph(&mut self, text: &str) {
        self.body.push_str(&format!("<p>{}</p>\n", escape(text)));
    }

    /// A table: a caption, the header cells, the rows.
    pub fn table(&mut self, caption: &str, header: &[String], rows: &[Vec<String>]) {
        self.body
            .push_str(&format!("<table>\n<caption>{}</caption>\n<tr>", escape(caption)));
        for h in header {
            self.body.push_str(&format!("<th>{}</th>", escape(h)));
        }
        self.body.push_str("</tr>\n");
        for r in rows {
            self.body.push_str("<tr>");
            for c in r {
                self.body.push_str(&format!("<td>{}</td>", escape(c)));
            }
            self.body.push_str("</tr>\n");
        }
        self.body.push_str("</table>\n");
    }

    /// A figure: SVG made by [`crate::plots`] (trusted: imutherm drew it,
    /// and every text in it was passed through plotters' own escaping) with
    /// a caption.
    pub fn figure(&mut self, svg: &str, caption: &str) {
        self.body.push_str(&format!(
            "<figure class=\"plot\">{svg}<figcaption>{}</figcaption></figure>\n",
            escape(caption)
        ));
    }

    /// An interactive 3D surface σ(τ, T) (drag to turn it), drawn on a
    /// canvas by a few lines of script embedded in the page, so the report
    /// needs no network and no library. `rows` are (mean temperature °C,
    /// [(τ s, σ)]) per slice.
    pub fn surface3d(&mut self, title: &str, unit: &str, rows: &[(f64, Vec<(f64, f64)>)]) {
        let id = self.surfaces;
        self.surfaces += 1;
        let mut data = String::from("[");
        for (i, (t, pts)) in rows.iter().filter(|r| r.0.is_finite()).enumerate() {
            if i > 0 {
                data.push(',');
            }
            data.push_str(&format!("{{\"t\":{t},\"p\":["));
            for (j, (tau, dev)) in pts.iter().filter(|p| p.0 > 0.0 && p.1 > 0.0).enumerate() {
                if j > 0 {
                    data.push(',');
                }
                data.push_str(&format!("[{},{}]", tau.log10(), dev.log10()));
            }
            data.push_str("]}");
        }
        data.push(']');
        if id == 0 {
            self.body.push_str(&format!("<script>{SURFACE_JS}</script>\n"));
        }
        self.body.push_str(&format!(
            "<figure class=\"surface\"><canvas id=\"surface{id}\" width=\"640\" height=\"460\" data-title=\"{}\" data-unit=\"{}\"></canvas>\
             <script type=\"application/json\" id=\"surface{id}-data\">{data}</script>\
             <script>imuthermSurface(\"surface{id}\");</script><figcaption>{}: drag to turn; x log₁₀ τ [s], y temperature [°C], z log₁₀ σ [{}]</figcaption></figure>\n",
            escape(title),
            escape(unit),
            escape(title),
            escape(unit)
        ));
    }

    /// A preformatted block (a command line).
    pub fn code(&mut self, text: &str) {
        self.body.push_str(&format!("<pre>{}</pre>\n", escape(text)));
    }

    /// The finished page.
    pub fn finish(&self) -> String {
        format!(
            "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>{}</title>\n<style>{STYLE}</style>\n</head>\n<body>\n<h1>{}</h1>\n{}</body>\n</html>\n",
            escape(&self.title),
            escape(&self.title),
            self.body
        )
    }
}

/// The 3D surface: project each cell of the (log τ, T, log σ) grid, sort the
/// quads back to front, fill them by height. Marks the canvas
/// `data-rendered` when done, which the browser test reads.
const SURFACE_JS: &str = r#"
function imuthermSurface(id){
 var c=document.getElementById(id),g=c.getContext('2d');
 var rows=JSON.parse(document.getElementById(id+'-data').textContent);
 var xs=[],ys=[],zs=[];
 rows.forEach(function(r){r.p.forEach(function(q){xs.push(q[0]);zs.push(q[1]);});ys.push(r.t);});
 function rng(a){var lo=Math.min.apply(null,a),hi=Math.max.apply(null,a);return [lo,hi>lo?hi:lo+1];}
 var X=rng(xs),Y=rng(ys),Z=rng(zs),yaw=-0.7,pitch=0.5;
 function n(v,r){return (v-r[0])/(r[1]-r[0])-0.5;}
 function heat(v){var s=[[68,1,84],[59,82,139],[33,145,140],[94,201,98],[253,231,37]];
  var x=Math.max(0,Math.min(1,v))*4,i=Math.min(3,Math.floor(x)),f=x-i,a=s[i],b=s[i+1];
  return 'rgb('+[0,1,2].map(function(k){return Math.round(a[k]+(b[k]-a[k])*f);}).join(',')+')';}
 function proj(x,y,z){var cx=Math.cos(yaw),sx=Math.sin(yaw),cp=Math.cos(pitch),sp=Math.sin(pitch);
  var x1=x*cx-y*sx,y1=x*sx+y*cx,z1=z*cp-y1*sp,d=y1*cp+z*sp;
  return [c.width/2+x1*360,c.height/2-z1*300,d];}
 function draw(){g.fillStyle='#fff';g.fillRect(0,0,c.width,c.height);var quads=[];
  for(var i=0;i+1<rows.length;i++){var a=rows[i],b=rows[i+1];
   for(var j=0;j+1<Math.min(a.p.length,b.p.length);j++){
    var pts=[[a.p[j][0],a.t,a.p[j][1]],[a.p[j+1][0],a.t,a.p[j+1][1]],[b.p[j+1][0],b.t,b.p[j+1][1]],[b.p[j][0],b.t,b.p[j][1]]];
    var pr=pts.map(function(p){return proj(n(p[0],X),n(p[1],Y),n(p[2],Z));});
    var h=pts.reduce(function(s,p){return s+n(p[2],Z)+0.5;},0)/4;
    quads.push({p:pr,d:pr.reduce(function(s,q){return s+q[2];},0),h:h});}}
  quads.sort(function(u,v){return v.d-u.d;});
  quads.forEach(function(q){g.beginPath();g.moveTo(q.p[0][0],q.p[0][1]);
   for(var k=1;k<4;k++){g.lineTo(q.p[k][0],q.p[k][1]);}g.closePath();
   g.fillStyle=heat(q.h);g.fill();g.strokeStyle='rgba(0,0,0,0.25)';g.stroke();});
  g.fillStyle='#222';g.font='14px sans-serif';g.fillText(c.dataset.title+' — σ(τ, T) ['+c.dataset.unit+']',10,20);
  c.dataset.rendered=String(quads.length);}
 var drag=null;c.addEventListener('mousedown',function(e){drag=[e.clientX,e.clientY];});
 window.addEventListener('mouseup',function(){drag=null;});
 c.addEventListener('mousemove',function(e){if(!drag)return;yaw+=(e.clientX-drag[0])*0.01;
  pitch=Math.max(-1.5,Math.min(1.5,pitch+(e.clientY-drag[1])*0.01));drag=[e.clientX,e.clientY];draw();});
 draw();}
"#;

const STYLE: &str = "body{font-family:sans-serif;max-width:1100px;margin:2em auto;padding:0 1em;color:#222}\
table{border-collapse:collapse;margin:1em 0}td,th{border:1px solid #bbb;padding:.25em .6em;text-align:right}\
th{background:#eee}caption{font-weight:bold;text-align:left;padding:.3em 0}figure.plot{display:inline-block;margin:.5em}\
figure.surface{display:inline-block;margin:.5em}canvas{border:1px solid #ddd;cursor:grab}figcaption{font-size:.9em;color:#555}pre{background:#f4f4f4;padding:.6em;overflow-x:auto}";

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn file_text_is_escaped() {
        let mut p = Page::new("report");
        p.table(
            "inputs",
            &["file".to_string()],
            &[vec!["<script>alert(1)</script>.txt".to_string()]],
        );
        let html = p.finish();
        assert!(html.contains("&lt;script&gt;alert(1)&lt;/script&gt;.txt"));
        assert!(!html.contains("<script>"));
    }
}
