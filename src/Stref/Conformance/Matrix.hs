-- | The compatibility matrix (docs/engines.md): every dialect's corpus run
-- against every engine, kept as data (@docs/matrix/matrix.json@) and shown
-- as one static page (@docs/matrix/index.html@) that reads the same data.
--
-- The data holds, per engine and dialect, the totals and every case's
-- result with its first difference; per rule, its title. The page counts
-- from the data in the browser, so what it shows is the JSON's by
-- construction; its elements carry @data-@ attributes for tests.
module Stref.Conformance.Matrix
  ( MatrixRun (..)
  , matrixData
  , matrixPage
  ) where

import Data.Aeson (Value, object, (.=))
import qualified Data.Aeson as A
import qualified Data.ByteString.Lazy as BL
import Data.List.NonEmpty (NonEmpty (..))
import qualified Data.Map.Strict as M
import Data.Text (Text)
import qualified Data.Text as T
import qualified Data.Text.Encoding as TE
import Stref.Conformance.Case (Case (..))
import Stref.Conformance.Report (outcomeName, totals, totalsJson)
import Stref.Conformance.Runner (CaseResult (..), Difference (..), Outcome (..))

-- | One engine's run of one dialect's corpus.
data MatrixRun = MatrixRun
  { mrEngine :: Text
  , mrTitle :: Text
  , mrVersion :: Text -- ^ what the engine says of itself, and what the user said of it
  , mrDialect :: Text
  , mrResults :: [CaseResult]
  }

-- | The matrix as data: when and from which stref commit it was measured,
-- the rules' titles, and each run.
matrixData :: Text -> Text -> M.Map Text Text -> [MatrixRun] -> Value
matrixData date commit titles runs =
  object
    [ "format" .= ("stref-matrix/1" :: Text)
    , "date" .= date
    , "stref" .= commit
    , "rules" .= titles
    , "runs" .= map run runs
    ]
  where
    run r =
      object
        [ "engine" .= mrEngine r
        , "title" .= mrTitle r
        , "version" .= mrVersion r
        , "dialect" .= mrDialect r
        , "totals" .= totalsJson (totals (mrResults r))
        , "cases" .= map caseValue (mrResults r)
        ]
    caseValue c =
      object $
        [ "id" .= resId c
        , "file" .= resFile c
        , "area" .= maybe "" caseArea (resCase c)
        , "rules" .= maybe [] caseRules (resCase c)
        , "result" .= outcomeName (resOutcome c)
        ]
          ++ case resOutcome c of
            Fail (d :| _) -> ["what" .= dWhat d, "expected" .= dExpected d, "actual" .= dActual d]
            InvalidCase e -> ["actual" .= e]
            Unsupported e -> ["actual" .= e]
            EngineError e -> ["actual" .= e]
            Skipped e -> ["actual" .= e]
            Pass -> []

-- | The page: the data embedded, and a script that draws the tables from
-- it (so the counts are the data's), with filters by engine and area.
matrixPage :: Value -> Text
matrixPage v =
  T.unlines
    [ "<!DOCTYPE html>"
    , "<html lang=\"en\"><head><meta charset=\"utf-8\">"
    , "<title>stref: where ST engines stand</title>"
    , "<style>"
    , "body{font-family:system-ui,sans-serif;margin:2em;max-width:80em;color:#222}"
    , "table{border-collapse:collapse;margin:1em 0}th,td{border:1px solid #ccc;padding:.25em .6em;text-align:right}"
    , "th{background:#f4f4f4}td.name,th.name{text-align:left}.pass{background:#e6f4e6}.fail{background:#fbe7e7}.unsupported{background:#f3f0dc}"
    , "details{margin:.2em 0}summary{cursor:pointer}code,pre{background:#f6f6f6;padding:0 .2em}.muted{color:#777}"
    , "</style></head><body>"
    , "<h1>Where ST engines stand</h1>"
    , "<p id=\"meta\" class=\"muted\"></p>"
    , "<p>Each engine ran each dialect's conformance corpus through its stref adapter (docs/engines.md). A case passes when the engine leaves every value the case states, or rejects the program where the case says it is rejected.</p>"
    , "<p><label>Engine <select id=\"engine\"><option value=\"\">all</option></select></label> "
    , "<label>Area <select id=\"area\"><option value=\"\">all</option></select></label> "
    , "<label>Result <select id=\"result\"><option value=\"\">all</option><option>pass</option><option>fail</option><option>unsupported</option><option>engine-error</option></select></label></p>"
    , "<h2>Totals</h2><table id=\"totals\"></table>"
    , "<h2>By area</h2><table id=\"areas\"></table>"
    , "<h2>By rule</h2><table id=\"rules\"></table>"
    , "<h2>Cases</h2><p id=\"shown\" class=\"muted\"></p><div id=\"cases\"></div>"
    , "<script type=\"application/json\" id=\"data\">" <> T.replace "</" "<\\/" (TE.decodeUtf8 (BL.toStrict (A.encode v))) <> "</script>"
    , "<script>"
    , script
    , "</script></body></html>"
    ]

script :: Text
script =
  T.unlines
    [ "const D = JSON.parse(document.getElementById('data').textContent);"
    , "const $ = id => document.getElementById(id);"
    , "const esc = s => String(s).replace(/[&<>\"]/g, c => ({'&':'&amp;','<':'&lt;','>':'&gt;','\"':'&quot;'}[c]));"
    , "const KINDS = ['pass', 'fail', 'unsupported', 'engine-error'];"
    , "const runName = r => r.engine + ' / ' + r.dialect;"
    , "$('meta').textContent = 'Measured ' + D.date + ' with stref ' + D.stref + '. ' + [...new Set(D.runs.map(r => r.title + ': ' + r.version))].join('; ');"
    , "for (const e of [...new Set(D.runs.map(r => r.engine))]) $('engine').insertAdjacentHTML('beforeend', '<option>' + esc(e) + '</option>');"
    , "const areas = [...new Set(D.runs.flatMap(r => r.cases.map(c => c.id.split('/').slice(0, 2).join('/'))))].sort();"
    , "for (const a of areas) $('area').insertAdjacentHTML('beforeend', '<option>' + esc(a) + '</option>');"
    , "function count(cases) { const n = {pass: 0, fail: 0, unsupported: 0, 'engine-error': 0}; for (const c of cases) if (c.result in n) n[c.result]++; return n; }"
    , "function cells(n, attrs) { return KINDS.map(k => '<td class=\"' + (n[k] ? k : '') + '\" ' + attrs + ' data-kind=\"' + k + '\">' + n[k] + '</td>').join(''); }"
    , "function draw() {"
    , "  const eng = $('engine').value, area = $('area').value, res = $('result').value;"
    , "  const runs = D.runs.filter(r => !eng || r.engine === eng);"
    , "  const inArea = c => !area || c.id.startsWith(area + '/');"
    , "  const head = '<tr><th class=\"name\"></th><th>passed</th><th>failed</th><th>unsupported</th><th>engine error</th></tr>';"
    , "  $('totals').innerHTML = head + runs.map(r => '<tr data-run=\"' + esc(runName(r)) + '\"><td class=\"name\">' + esc(r.title) + ' — ' + esc(r.dialect) + '</td>' + cells(count(r.cases.filter(inArea)), 'data-run=\"' + esc(runName(r)) + '\"') + '</tr>').join('');"
    , "  const areaRows = areas.filter(a => !area || a === area).map(a => '<tr><td class=\"name\">' + esc(a) + '</td>' + runs.map(r => { const n = count(r.cases.filter(c => c.id.startsWith(a + '/'))); const t = n.pass + n.fail + n.unsupported + n['engine-error']; return t ? '<td data-run=\"' + esc(runName(r)) + '\" data-area=\"' + esc(a) + '\">' + n.pass + ' / ' + t + '</td>' : '<td></td>'; }).join('') + '</tr>');"
    , "  $('areas').innerHTML = '<tr><th class=\"name\">area</th>' + runs.map(r => '<th>' + esc(runName(r)) + '<br>passed / cases</th>').join('') + '</tr>' + areaRows.join('');"
    , "  const ruleIds = [...new Set(runs.flatMap(r => r.cases.filter(inArea).flatMap(c => c.rules)))].sort();"
    , "  $('rules').innerHTML = '<tr><th class=\"name\">rule</th>' + runs.map(r => '<th>' + esc(runName(r)) + '</th>').join('') + '</tr>' + ruleIds.map(id => '<tr><td class=\"name\" title=\"' + esc(D.rules[id] || '') + '\">' + esc(id) + ' <span class=\"muted\">' + esc(D.rules[id] || '') + '</span></td>' + runs.map(r => { const n = count(r.cases.filter(c => inArea(c) && c.rules.includes(id))); const t = n.pass + n.fail + n.unsupported + n['engine-error']; return '<td class=\"' + (t && n.pass === t ? 'pass' : (n.fail ? 'fail' : '')) + '\">' + (t ? n.pass + ' / ' + t : '') + '</td>'; }).join('') + '</tr>').join('');"
    , "  const shown = runs.flatMap(r => r.cases.filter(c => inArea(c) && (res ? c.result === res : c.result !== 'pass')).map(c => [r, c]));"
    , "  $('shown').textContent = shown.length + ' cases' + (res ? ' with result ' + res : ' that did not pass');"
    , "  $('cases').innerHTML = shown.slice(0, 2000).map(([r, c]) => '<details data-case=\"' + esc(c.id) + '\" data-run=\"' + esc(runName(r)) + '\"><summary><span class=\"' + c.result + '\">' + c.result + '</span> ' + esc(r.engine) + ': ' + esc(c.id) + '</summary>'"
    , "    + '<p>Program: <a href=\"../../' + esc(c.file) + '\"><code>' + esc(c.file) + '</code></a></p>'"
    , "    + (c.what ? '<p><b>' + esc(c.what) + '</b>: expected <code>' + esc(c.expected) + '</code>, the engine gave <code>' + esc(c.actual) + '</code></p>' : (c.actual ? '<p>' + esc(c.actual) + '</p>' : ''))"
    , "    + '<p>Rules: ' + c.rules.map(id => '<code>' + esc(id) + '</code> ' + esc(D.rules[id] || '')).join('; ') + '</p></details>').join('');"
    , "}"
    , "for (const id of ['engine', 'area', 'result']) $(id).addEventListener('change', draw);"
    , "// a link may choose the filters: index.html#engine=matiec&area=tecomat/strings"
    , "for (const [k, v] of new URLSearchParams(location.hash.slice(1))) if ($(k) && [...$(k).options].some(o => o.value === v)) $(k).value = v;"
    , "draw();"
    ]
